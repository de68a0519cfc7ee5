// smoothView (preprocess/partial_view.h): PCL's moving least squares,
// compiled here from its templates (the precompiled ones live in
// pcl_surface, which links VTK); its own translation unit, outside the
// unity build, since PCL_NO_PRECOMPILE and the template code's warnings
// must not reach other files.
#define PCL_NO_PRECOMPILE
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/surface/mls.h>

#include <cmath>

#include "core/invalid_argument.h"
#include "preprocess/partial_view.h"

namespace hfts::preprocess {

SmoothedView smoothView(const Vertices& points, const Eigen::Vector3d& viewpoint, double radius) {
  checkViewPoints(points);
  if (!(radius > 0.0) || !std::isfinite(radius))
    throw InvalidArgument("smoothing", "must be a positive radius (m)");
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->resize(static_cast<std::size_t>(points.rows()));
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    (*cloud)[static_cast<std::size_t>(i)] =
        pcl::PointXYZ(static_cast<float>(points(i, 0)), static_cast<float>(points(i, 1)),
                      static_cast<float>(points(i, 2)));
  pcl::MovingLeastSquares<pcl::PointXYZ, pcl::PointNormal> mls;
  mls.setInputCloud(cloud);
  mls.setSearchMethod(
      pcl::search::KdTree<pcl::PointXYZ>::Ptr(new pcl::search::KdTree<pcl::PointXYZ>));
  mls.setSearchRadius(radius);
  mls.setPolynomialOrder(2);
  mls.setComputeNormals(true);
  pcl::PointCloud<pcl::PointNormal> fitted;
  mls.process(fitted);
  const pcl::PointIndicesPtr corresponding = mls.getCorrespondingIndices();
  SmoothedView out;
  out.points.resize(static_cast<Eigen::Index>(fitted.size()), 3);
  out.normals.resize(static_cast<Eigen::Index>(fitted.size()), 3);
  Eigen::Index kept = 0;
  for (std::size_t i = 0; i < fitted.size(); ++i) {
    const pcl::PointNormal& f = fitted[i];
    const Eigen::Vector3d p(f.x, f.y, f.z);
    Eigen::Vector3d n(f.normal_x, f.normal_y, f.normal_z);
    if (!p.allFinite() || !n.allFinite() || n.norm() < 0.5) continue;
    n.normalize();
    if (n.dot(viewpoint - p) < 0.0) n = -n;
    out.points.row(kept) = p.transpose();
    out.normals.row(kept) = n.transpose();
    out.source.push_back(static_cast<std::uint32_t>(corresponding->indices[i]));
    ++kept;
  }
  out.points.conservativeResize(kept, 3);
  out.normals.conservativeResize(kept, 3);
  return out;
}

}  // namespace hfts::preprocess
