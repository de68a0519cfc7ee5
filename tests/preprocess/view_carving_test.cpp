// Objects seen whole in depth images: where the cameras saw through is
// carved away, what no camera saw free (behind an occluder, under the
// lowest observed point) stays beside the solid, so the object is held
// even where the views never saw it.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/invalid_argument.h"
#include "preprocess/convex_hull.h"
#include "preprocess/database_builder.h"
#include "preprocess/partial_view.h"
#include "test_meshes.h"

namespace hfts::preprocess {
namespace {

struct Box {
  Eigen::Vector3d low, high;
};

/// The object: 6 x 4 x 10 cm standing on the floor at the origin; the
/// floor; a low wall between the object and the camera that hides the
/// lower part of its near side.
const Box kObject{{-0.03, -0.02, 0.0}, {0.03, 0.02, 0.10}};
const Box kFloor{{-1.0, -1.0, -0.02}, {1.0, 1.0, 0.0}};
const Box kWall{{0.10, -0.15, 0.0}, {0.12, 0.15, 0.06}};
const Eigen::Vector3d kEye(0.5, 0.05, 0.35);

/// Where a ray from `from` along `direction` first enters `box` (the slab
/// method), or infinity.
double entry(const Box& box, const Eigen::Vector3d& from, const Eigen::Vector3d& direction) {
  double near = 0.0, far = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (std::abs(direction[a]) < 1e-12) {
      if (from[a] < box.low[a] || from[a] > box.high[a]) return far;
      continue;
    }
    double t0 = (box.low[a] - from[a]) / direction[a], t1 = (box.high[a] - from[a]) / direction[a];
    if (t0 > t1) std::swap(t0, t1);
    near = std::max(near, t0);
    far = std::min(far, t1);
  }
  return near <= far ? near : std::numeric_limits<double>::infinity();
}

/// A noise-free depth image of the boxes (the first is the object) from
/// `eye` looking at `centre`: 320 x 240 pixels, 280 px focal length.
DepthEvidence render(const std::vector<Box>& boxes, const Eigen::Vector3d& eye,
                     const Eigen::Vector3d& centre) {
  DepthEvidence out;
  out.width = 320;
  out.height = 240;
  out.fx = out.fy = 280.0;
  out.cx = 159.5;
  out.cy = 119.5;
  const Eigen::Vector3d z = (centre - eye).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  out.camera.linear() << x, z.cross(x), z;
  out.camera.translation() = eye;
  out.depths.assign(std::size_t(out.width) * std::size_t(out.height), 0.0f);
  out.target.assign(out.depths.size(), 0);
  for (int v = 0; v < out.height; ++v)
    for (int u = 0; u < out.width; ++u) {
      // Along this ray the parameter of a point is its depth.
      const Eigen::Vector3d ray =
          out.camera.linear() * Eigen::Vector3d((u - out.cx) / out.fx, (v - out.cy) / out.fy, 1.0);
      double nearest = std::numeric_limits<double>::infinity();
      std::size_t hit = boxes.size();
      for (std::size_t b = 0; b < boxes.size(); ++b) {
        const double t = entry(boxes[b], eye, ray);
        if (t < nearest) {
          nearest = t;
          hit = b;
        }
      }
      if (hit == boxes.size()) continue;
      const std::size_t i = std::size_t(v) * std::size_t(out.width) + std::size_t(u);
      out.depths[i] = static_cast<float>(nearest);
      out.target[i] = hit == 0;
    }
  return out;
}

/// The object's pixels as points in the world.
Vertices objectPoints(const DepthEvidence& view) {
  std::vector<Eigen::Vector3d> points;
  for (int v = 0; v < view.height; ++v)
    for (int u = 0; u < view.width; ++u) {
      const std::size_t i = std::size_t(v) * std::size_t(view.width) + std::size_t(u);
      if (!view.target[i]) continue;
      const double d = static_cast<double>(view.depths[i]);
      points.push_back(view.camera * Eigen::Vector3d((u - view.cx) * d / view.fx,
                                                     (v - view.cy) * d / view.fy, d));
    }
  Vertices out(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    out.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
  return out;
}

/// Points on the object's faces, `step` apart.
std::vector<Eigen::Vector3d> objectSurface(double step) {
  std::vector<Eigen::Vector3d> out;
  const Eigen::Vector3d size = kObject.high - kObject.low;
  for (int a = 0; a < 3; ++a)
    for (const double side : {0.0, 1.0}) {
      const int b = (a + 1) % 3, c = (a + 2) % 3;
      for (double s = 0.0; s <= size[b] + 1e-9; s += step)
        for (double t = 0.0; t <= size[c] + 1e-9; t += step) {
          Eigen::Vector3d p = kObject.low;
          p[a] += side * size[a];
          p[b] += s;
          p[c] += t;
          out.push_back(p);
        }
    }
  return out;
}

/// How far `p` lies outside what the database holds: its solid and the
/// hidden boxes beside it (0 inside).
double outside(const db::ObjectDatabase& db, const Eigen::Vector3d& p) {
  const ConvexHull solid(db.geometry.hull_vertices, "solid");
  double best = std::max(0.0, -solid.depth(p));
  const db::PartialView& view = *db.partial_view;
  for (Eigen::Index b = 0; b < view.hidden_low.rows(); ++b) {
    const Eigen::Vector3d gap = (view.hidden_low.row(b).transpose() - p)
                                    .cwiseMax(p - view.hidden_high.row(b).transpose())
                                    .cwiseMax(0.0);
    best = std::min(best, gap.norm());
  }
  return best;
}

SensedView sensed(const DepthEvidence& image, bool withImage) {
  SensedView view;
  view.points = objectPoints(image);
  view.options.viewpoint = image.camera.translation();
  view.options.smoothing = 0.0;  // noise-free
  if (withImage) view.depth = image;
  return view;
}

TEST(ViewCarving, TheFloorIsTheSupportTheCamerasSaw) {
  const DepthEvidence image =
      render({kObject, kFloor, kWall}, kEye, Eigen::Vector3d(0.0, 0.0, 0.05));
  const Carving carving = carveViews({image}, objectPoints(image), 0.1, std::nullopt);
  EXPECT_TRUE(carving.floor_fitted);
  EXPECT_NEAR(carving.floor, 0.0, 0.003);
  EXPECT_DOUBLE_EQ(carving.voxel, 0.003);
  // The wall hides part of the object's outline, not all of it.
  ASSERT_EQ(carving.occluded.size(), 1u);
  EXPECT_GT(carving.occluded[0], 5u);
  EXPECT_LT(carving.occluded[0], carving.outline[0]);
  // A floor given is taken as it is.
  EXPECT_DOUBLE_EQ(carveViews({image}, objectPoints(image), 0.1, 0.01).floor, 0.01);
  EXPECT_FALSE(carveViews({image}, objectPoints(image), 0.1, 0.01).floor_fitted);
}

TEST(ViewCarving, WhatAWallHidesIsHeldBesideTheSolid) {
  const DepthEvidence image =
      render({kObject, kFloor, kWall}, kEye, Eigen::Vector3d(0.0, 0.0, 0.05));
  const db::BuildParameters params;
  // From the points alone the solid misses what the wall hides: the lowest
  // point seen is the floor of its shadows.
  const db::ObjectDatabase points =
      buildObjectDatabaseFromViews({sensed(image, false)}, params, "points").database;
  double worst = 0.0;
  for (const Eigen::Vector3d& p : objectSurface(0.005)) worst = std::max(worst, outside(points, p));
  EXPECT_GT(worst, 0.005);
  EXPECT_EQ(points.partial_view->hidden_low.rows(), 0);
  // With the image, every point of the object lies in the solid or the
  // hidden space beside it, to the carving's voxel (3 mm: half its
  // diagonal).
  const BuildResult carved = buildObjectDatabaseFromViews({sensed(image, true)}, params, "image");
  const db::ObjectDatabase& db = carved.database;
  ASSERT_GT(db.partial_view->hidden_low.rows(), 0);
  for (const Eigen::Vector3d& p : objectSurface(0.005)) EXPECT_LE(outside(db, p), 0.0026) << p;
  // The floor the shadows stop at is the support seen, not the lowest
  // point; the solid stands on it: no corner is left just above it.
  const double floor = db.partial_view->floors[0];
  EXPECT_NEAR(floor, 0.0, 0.003);
  const ConvexHull solid(db.geometry.hull_vertices, "solid");
  int feet = 0;
  for (Eigen::Index v = 0; v < db.geometry.hull_vertices.rows(); ++v) {
    Eigen::Vector3d corner = db.geometry.hull_vertices.row(v).transpose();
    EXPECT_GE(corner.z(), floor - 1e-9);
    if (corner.z() > floor + kFootHeight) continue;
    corner.z() = floor;
    EXPECT_GE(solid.depth(corner), -1e-6) << corner.transpose();
    ++feet;
  }
  EXPECT_GT(feet, 2);
  // No contact lies in the hidden space; the occlusion is reported.
  for (Eigen::Index c = 0; c < db.positions.rows(); ++c)
    for (Eigen::Index b = 0; b < db.partial_view->hidden_low.rows(); ++b) {
      const Eigen::Vector3d p = db.positions.row(c).transpose();
      const double depth =
          std::min((p - db.partial_view->hidden_low.row(b).transpose()).minCoeff(),
                   (db.partial_view->hidden_high.row(b).transpose() - p).minCoeff());
      EXPECT_LE(depth, kMaxViewContactDepth);
    }
  EXPECT_TRUE(std::any_of(carved.warnings.begin(), carved.warnings.end(), [](const std::string& w) {
    return w.find("outline border a nearer surface") != std::string::npos;
  }));
}

TEST(ViewCarving, TwoCamerasCarveWhatOneLeavesOpen) {
  const Eigen::Vector3d centre(0.0, 0.0, 0.05);
  const DepthEvidence front = render({kObject, kFloor, kWall}, kEye, centre);
  const DepthEvidence side =
      render({kObject, kFloor, kWall}, Eigen::Vector3d(0.0, 0.5, 0.35), centre);
  const db::BuildParameters params;
  const db::ObjectDatabase one =
      buildObjectDatabaseFromViews({sensed(front, true)}, params, "one").database;
  const BuildResult built =
      buildObjectDatabaseFromViews({sensed(front, true), sensed(side, true)}, params, "two");
  const db::ObjectDatabase& two = built.database;
  const auto hiddenVolume = [](const db::ObjectDatabase& db) {
    double sum = 0.0;
    for (Eigen::Index b = 0; b < db.partial_view->hidden_low.rows(); ++b)
      sum += (db.partial_view->hidden_high.row(b) - db.partial_view->hidden_low.row(b)).prod();
    return sum;
  };
  EXPECT_LT(hiddenVolume(two), 0.5 * hiddenVolume(one));
  for (const Eigen::Vector3d& p : objectSurface(0.005)) EXPECT_LE(outside(two, p), 0.0026) << p;
  // The wall hides part of the object from the front camera (view 0); its hull,
  // with the side camera's points added, still cuts the side camera's
  // solid down, and the solid holds every point either camera saw.
  const db::ObjectDatabase side_only =
      buildObjectDatabaseFromViews({sensed(side, true)}, params, "side").database;
  EXPECT_TRUE(std::any_of(built.warnings.begin(), built.warnings.end(), [](const std::string& w) {
    return w.find("view 0: ") != std::string::npos &&
           w.find("outline border a nearer surface") != std::string::npos;
  }));
  EXPECT_LT(two.geometry.volume, 0.8 * side_only.geometry.volume);
  const ConvexHull solid(two.geometry.hull_vertices, "solid");
  for (const DepthEvidence* view : {&front, &side}) {
    const Vertices seen = objectPoints(*view);
    for (Eigen::Index i = 0; i < seen.rows(); ++i)
      EXPECT_GE(solid.depth(seen.row(i).transpose()), -1e-6);
  }
}

TEST(ViewCarving, BadImagesAreNamed) {
  DepthEvidence image = render({kObject, kFloor}, kEye, Eigen::Vector3d(0.0, 0.0, 0.05));
  const Vertices points = objectPoints(image);
  const auto field = [&](const DepthEvidence& view, double reach) {
    try {
      carveViews({view}, points, reach, std::nullopt);
    } catch (const InvalidArgument& e) {
      return e.field();
    }
    return std::string("none");
  };
  EXPECT_EQ(field(image, 0.0), "reach");
  DepthEvidence smallMask = image;
  smallMask.target.pop_back();
  EXPECT_EQ(field(smallMask, 0.1), "depth");
  DepthEvidence noFocus = image;
  noFocus.fx = 0.0;
  EXPECT_EQ(field(noFocus, 0.1), "depth");
  EXPECT_THROW(carveViews({}, points, 0.1, std::nullopt), InvalidArgument);
  EXPECT_THROW(carveViews({image}, points, 0.1, 1.0), InvalidArgument);  // above every point
}

TEST(ViewCarving, MergedVoxelsAreTheCubesAndNoMore) {
  // A 3 x 3 x 3 block and one cube apart: two boxes.
  std::vector<Eigen::Vector3d> centres;
  for (int x = 0; x < 3; ++x)
    for (int y = 0; y < 3; ++y)
      for (int z = 0; z < 3; ++z) centres.emplace_back(0.01 * x, 0.01 * y, 0.01 * z);
  centres.emplace_back(0.05, 0.0, 0.0);
  Vertices points(static_cast<Eigen::Index>(centres.size()), 3);
  for (std::size_t i = 0; i < centres.size(); ++i)
    points.row(static_cast<Eigen::Index>(i)) = centres[i].transpose();
  const auto boxes = mergedVoxels(points, 0.01);
  ASSERT_EQ(boxes.size(), 2u);
  double volume = 0.0;
  for (const auto& [low, high] : boxes) volume += (high - low).prod();
  EXPECT_NEAR(volume, 28e-6, 1e-12);
  EXPECT_TRUE(boxes[0].first.isApprox(Eigen::Vector3d(-0.005, -0.005, -0.005)));
  EXPECT_TRUE(boxes[0].second.isApprox(Eigen::Vector3d(0.025, 0.025, 0.025)));
  EXPECT_TRUE(mergedVoxels(Vertices(0, 3), 0.01).empty());
  EXPECT_THROW(mergedVoxels(points, 0.0), InvalidArgument);
}

TEST(ViewCarving, HiddenBoxesGoThroughTheFile) {
  const DepthEvidence image =
      render({kObject, kFloor, kWall}, kEye, Eigen::Vector3d(0.0, 0.0, 0.05));
  db::ObjectDatabase db =
      buildObjectDatabaseFromViews({sensed(image, true)}, db::BuildParameters{}, "image").database;
  db.name = "walled";
  const test::TempDir dir;
  const std::filesystem::path path = dir.path() / "walled.h5";
  db::saveObjectDatabase(db, path);
  const db::ObjectDatabase read = db::loadObjectDatabase(path);
  EXPECT_EQ(read.partial_view->hidden_low, db.partial_view->hidden_low);
  EXPECT_EQ(read.partial_view->hidden_high, db.partial_view->hidden_high);
  // A box whose corners are the wrong way round is refused.
  db.partial_view->hidden_high(0, 2) = db.partial_view->hidden_low(0, 2) - 0.001;
  EXPECT_THROW(db::saveObjectDatabase(db, path), db::DatabaseError);
}

}  // namespace
}  // namespace hfts::preprocess
