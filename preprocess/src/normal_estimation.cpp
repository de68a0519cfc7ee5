// Normals and curvature from PCL.
#include <pcl/features/normal_3d.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>

#include <cmath>
#include <stdexcept>

#include "preprocess/contact_set.h"

namespace hfts::preprocess {
namespace {

/// Neighbours whose sampled side faces away by more than 120 degrees are
/// on another surface (e.g. the inside of a thin wall).
constexpr double kSameSideCosine = -0.5;

}  // namespace

void ContactSet::keep(const std::vector<bool>& mask) {
  if (mask.size() != size()) throw std::logic_error("ContactSet::keep: mask size mismatch");
  Eigen::Index out = 0;
  for (Eigen::Index i = 0; i < positions.rows(); ++i) {
    if (!mask[static_cast<std::size_t>(i)]) continue;
    positions.row(out) = positions.row(i);
    normals.row(out) = normals.row(i);
    curvature(out) = curvature(i);
    ++out;
  }
  positions.conservativeResize(out, 3);
  normals.conservativeResize(out, 3);
  curvature.conservativeResize(out);
}

static pcl::PointCloud<pcl::PointXYZ>::Ptr toCloud(const Vertices& positions) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->resize(static_cast<std::size_t>(positions.rows()));
  for (Eigen::Index i = 0; i < positions.rows(); ++i) {
    (*cloud)[static_cast<std::size_t>(i)] =
        pcl::PointXYZ(static_cast<float>(positions(i, 0)), static_cast<float>(positions(i, 1)),
                      static_cast<float>(positions(i, 2)));
  }
  return cloud;
}

ContactSet estimateNormals(const Vertices& positions, const Vertices& sideNormals,
                           const SurfacePoints& support, double patch_radius) {
  if (!(patch_radius > 0.0)) throw std::invalid_argument("patch radius must be positive");
  if (support.positions.rows() != support.sides.rows())
    throw std::invalid_argument("support points and sides differ in number");
  ContactSet contacts;
  contacts.positions = positions;
  contacts.normals = sideNormals;
  contacts.curvature = Eigen::VectorXd::Constant(positions.rows(), 1.0 / 3.0);
  if (positions.rows() == 0 || support.positions.rows() == 0) return contacts;

  const pcl::PointCloud<pcl::PointXYZ>::Ptr cloud = toCloud(support.positions);
  const pcl::PointCloud<pcl::PointXYZ>::Ptr queries = toCloud(positions);
  pcl::search::KdTree<pcl::PointXYZ> tree;
  tree.setInputCloud(cloud);
  pcl::Indices neighbours, sameSide;
  std::vector<float> squaredDistances;
  for (Eigen::Index i = 0; i < positions.rows(); ++i) {
    const Eigen::Vector3d side = sideNormals.row(i).transpose();
    tree.radiusSearch((*queries)[static_cast<std::size_t>(i)], patch_radius, neighbours,
                      squaredDistances);
    // Only neighbours seen from the same side belong to the patch: the far
    // side of a thin wall lies within the radius but is another surface.
    sameSide.clear();
    for (const pcl::index_t j : neighbours)
      if (side.dot(support.sides.row(j).transpose()) > kSameSideCosine) sameSide.push_back(j);
    Eigen::Vector4f plane;
    float curvature = 0.0f;
    if (sameSide.size() < 3 || !pcl::computePointNormal(*cloud, sameSide, plane, curvature))
      continue;
    Eigen::Vector3d normal = plane.head<3>().cast<double>();
    if (!normal.allFinite() || !std::isfinite(curvature) || normal.norm() < 0.5) continue;
    normal.normalize();
    if (normal.dot(side) < 0.0) normal = -normal;
    contacts.normals.row(i) = normal.transpose();
    contacts.curvature(i) = curvature;
  }
  return contacts;
}

ContactSet estimateNormals(const Vertices& positions, const Vertices& sideNormals,
                           double patch_radius) {
  return estimateNormals(positions, sideNormals, {positions, sideNormals}, patch_radius);
}

}  // namespace hfts::preprocess
