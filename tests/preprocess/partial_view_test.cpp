// Objects seen from one side: the conservative hidden side, the contacts
// on observed points only, and the database's record of the view.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "core/invalid_argument.h"
#include "preprocess/convex_hull.h"
#include "preprocess/database_builder.h"
#include "preprocess/partial_view.h"
#include "test_meshes.h"

namespace hfts::preprocess {
namespace {

/// A box standing on z = 0, centred on the z axis.
struct Box {
  Eigen::Vector3d size{0.06, 0.04, 0.10};
  Eigen::Vector3d center() const { return {0.0, 0.0, size.z() / 2.0}; }
  std::vector<Eigen::Vector3d> corners() const {
    std::vector<Eigen::Vector3d> out;
    for (int i = 0; i < 8; ++i)
      out.push_back(center() + 0.5 * Eigen::Vector3d((i & 1) ? size.x() : -size.x(),
                                                     (i & 2) ? size.y() : -size.y(),
                                                     (i & 4) ? size.z() : -size.z()));
    return out;
  }
};

/// What a camera at `eye` sees of the box: points on the faces turned
/// towards it (a convex solid hides nothing else), `spacing` apart, moved
/// along the camera's ray by Gaussian noise of `sigma`; with each point,
/// its face's outward normal.
struct View {
  Vertices points;
  Vertices normals;
};
View viewOf(const Box& box, const Eigen::Vector3d& eye, double spacing, double sigma) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<Eigen::Vector3d> points, normals;
  for (int axis = 0; axis < 3; ++axis)
    for (const double sign : {-1.0, 1.0}) {
      Eigen::Vector3d n = Eigen::Vector3d::Zero();
      n[axis] = sign;
      const Eigen::Vector3d c = box.center() + 0.5 * sign * box.size[axis] * n.cwiseAbs();
      if (n.dot(eye - c) <= 0.0) continue;  // turned away
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (double a = -box.size[u] / 2; a <= box.size[u] / 2 + 1e-12; a += spacing)
        for (double b = -box.size[v] / 2; b <= box.size[v] / 2 + 1e-12; b += spacing) {
          Eigen::Vector3d p = c;
          p[u] += a;
          p[v] += b;
          p += noise(rng) * (p - eye).normalized();
          points.push_back(p);
          normals.push_back(n);
        }
    }
  View out;
  out.points.resize(static_cast<Eigen::Index>(points.size()), 3);
  out.normals.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i) {
    out.points.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
    out.normals.row(static_cast<Eigen::Index>(i)) = normals[i].transpose();
  }
  return out;
}

const Eigen::Vector3d kEye(0.5, 0.2, 0.4);

/// Seen from `eye`, the other options their defaults but hidden_depth.
ViewOptions from(const Eigen::Vector3d& eye, double hiddenDepth = 0.0) {
  ViewOptions o;
  o.viewpoint = eye;
  o.hidden_depth = hiddenDepth;
  return o;
}

TEST(PartialView, TheHullOfPointsAndShadowsHoldsTheWholeObject) {
  const Box box;
  const View view = viewOf(box, kEye, 0.002, 0.0);
  const HiddenSide hidden = hiddenSide(view.points, {kEye, 0.0, std::nullopt});
  EXPECT_NEAR(hidden.floor, 0.0, 1e-12);          // the lowest point
  EXPECT_NEAR(hidden.hidden_depth, 0.10, 1e-12);  // the largest edge
  const ConvexHull hull(hidden.corners, "view");
  // The far corners were never seen, and lie inside all the same.
  for (const Eigen::Vector3d& corner : box.corners()) EXPECT_GE(hull.depth(corner), -1e-9);
  // Nothing reaches below the floor.
  EXPECT_GE(hidden.corners.col(2).minCoeff(), -1e-12);
  // Conservative, not boundless: within the shadow's reach of the box.
  EXPECT_LE((hidden.corners.colwise().maxCoeff() - hidden.corners.colwise().minCoeff()).maxCoeff(),
            0.10 + 0.10);
}

TEST(PartialView, AShadowShorterThanTheObjectMissesItsFarSide) {
  const Box box;
  const View view = viewOf(box, kEye, 0.002, 0.0);
  const HiddenSide hidden = hiddenSide(view.points, {kEye, 0.01, std::nullopt});
  const ConvexHull hull(hidden.corners, "view");
  double deepest = 0.0;
  for (const Eigen::Vector3d& corner : box.corners())
    deepest = std::min(deepest, hull.depth(corner));
  EXPECT_LT(deepest, -0.01);  // the corner farthest from the camera lies outside
}

TEST(PartialView, AFloorCutsTheShadows) {
  const Box box;
  const View view = viewOf(box, kEye, 0.002, 0.0);
  const HiddenSide hidden = hiddenSide(view.points, {kEye, 0.5, 0.03});
  EXPECT_EQ(hidden.floor, 0.03);
  // Points above the floor cast no shadow below it; points below cast none.
  for (Eigen::Index i = 0; i < view.points.rows(); ++i) {
    const double z = view.points(i, 2);
    EXPECT_GE(hidden.corners(2 * i + 1, 2), std::min(z, 0.03) - 1e-9);
  }
}

TEST(PartialView, BadViewsAreNamed) {
  const View view = viewOf(Box{}, kEye, 0.01, 0.0);
  const auto field = [](const Vertices& points, const ViewOptions& options) {
    try {
      hiddenSide(points, options);
    } catch (const InvalidArgument& e) {
      return e.field();
    }
    return std::string("none");
  };
  EXPECT_EQ(field(view.points.topRows(3), {kEye, 0.0, std::nullopt}), "points");
  Vertices nan = view.points;
  nan(1, 1) = std::nan("");
  EXPECT_EQ(field(nan, {kEye, 0.0, std::nullopt}), "points");
  EXPECT_EQ(field(view.points, {Eigen::Vector3d::Constant(INFINITY), 0.0, std::nullopt}),
            "viewpoint");
  EXPECT_EQ(field(view.points, {view.points.row(4).transpose(), 0.0, std::nullopt}), "viewpoint");
  EXPECT_EQ(field(view.points, {kEye, -0.1, std::nullopt}), "hidden_depth");
  EXPECT_EQ(field(view.points, {kEye, 0.0, 1.0}), "floor");
  EXPECT_EQ(field(view.points, {kEye, 0.0, std::nan("")}), "floor");
  EXPECT_EQ(field(view.points, {kEye, 0.0, std::nullopt}), "none");
}

TEST(PartialView, OnePerVoxelKeepsTheFirstPointOfEachCube) {
  Vertices points(5, 3);
  points << 0.001, 0.001, 0.001,  //
      0.009, 0.002, 0.003,        // same 1 cm cube as the first
      0.011, 0.0, 0.0,            //
      -0.001, 0.0, 0.0,           // the cube below zero
      0.012, 0.001, 0.001;        // same as the third
  EXPECT_EQ(onePerVoxel(points, 0.01), (std::vector<std::uint32_t>{0, 2, 3}));
  EXPECT_EQ(onePerVoxel(points, 0.001).size(), 5u);
  EXPECT_THROW(onePerVoxel(points, 0.0), InvalidArgument);
}

TEST(PartialView, SmoothingTakesTheNoiseOut) {
  const Box box;
  const double sigma = 0.0015;
  const View view = viewOf(box, kEye, 0.001, sigma);
  const SmoothedView smoothed = smoothView(view.points, kEye, 0.01);
  ASSERT_GT(smoothed.points.rows(), view.points.rows() * 9 / 10);
  // Distance to the box's surface, before and after, away from its edges.
  const auto offSurface = [&](const Vertices& points) {
    double sum = 0.0;
    int n = 0;
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
      const Eigen::Vector3d q = points.row(i).transpose() - box.center();
      const Eigen::Vector3d g = q.cwiseAbs() - box.size / 2;
      std::array<double, 3> gap{g.x(), g.y(), g.z()};
      std::sort(gap.begin(), gap.end());
      if (gap[1] > -0.01) continue;  // within 1 cm of an edge
      sum += gap[2] * gap[2];
      ++n;
    }
    return std::sqrt(sum / n);
  };
  // The noise is along the camera's rays, seen 45-70 degrees off the faces.
  const double raw = offSurface(view.points);
  EXPECT_GT(raw, 0.3 * sigma);
  EXPECT_LT(offSurface(smoothed.points), 0.3 * raw);
  for (Eigen::Index i = 0; i < smoothed.points.rows(); ++i) {
    EXPECT_NEAR(smoothed.normals.row(i).norm(), 1.0, 1e-9);
    EXPECT_GT(smoothed.normals.row(i).dot(kEye.transpose() - smoothed.points.row(i)), 0.0);
    EXPECT_LT(smoothed.source[static_cast<std::size_t>(i)], view.points.rows());
  }
  EXPECT_THROW(smoothView(view.points, kEye, 0.0), InvalidArgument);
}

/// The database of a view of the box, as hfts-preprocess builds it.
BuildResult boxDatabase(const View& view, const Vertices* normals = nullptr,
                        double smoothing = ViewOptions{}.smoothing) {
  SensedView sensed{view.points, std::nullopt, {kEye, 0.0, std::nullopt, smoothing}};
  if (normals != nullptr) sensed.normals = *normals;
  return buildObjectDatabaseFromViews({sensed}, db::BuildParameters{}, "box view");
}

TEST(PartialView, ContactsAreObservedPointsFacingTheCamera) {
  const Box box;
  const double sigma = 0.001;
  const View view = viewOf(box, kEye, 0.001, sigma);
  const BuildResult r = boxDatabase(view);
  const db::ObjectDatabase& db = r.database;
  EXPECT_NO_THROW(db::validateObjectDatabase(db, "box view"));
  ASSERT_TRUE(db.partial_view.has_value());
  EXPECT_EQ(db.partial_view->viewpoints.row(0).transpose(), kEye);
  EXPECT_EQ(db.partial_view->points,
            std::vector<std::uint64_t>{static_cast<std::uint64_t>(view.points.rows())});
  EXPECT_GT(db.numContacts(), 500u);
  EXPECT_EQ(db.levels.front().size(), 20u);
  // Each contact is one of the view's points, smoothed (moved by no more
  // than the noise), its normal turned to the camera and, away from the
  // edges, within 15 degrees of its face's.
  std::size_t agree = 0;
  for (std::size_t c = 0; c < db.numContacts(); ++c) {
    const Eigen::Vector3d p = db.positions.row(static_cast<Eigen::Index>(c)).transpose();
    Eigen::Index nearest = 0;
    const double gap = (view.points.rowwise() - p.transpose()).rowwise().norm().minCoeff(&nearest);
    EXPECT_LT(gap, 3 * sigma);
    const Eigen::Vector3d n = db.normals.row(static_cast<Eigen::Index>(c)).transpose();
    EXPECT_GT(n.dot(kEye - p), 0.0);
    if (n.dot(view.normals.row(nearest).transpose()) > std::cos(15.0 * M_PI / 180.0)) ++agree;
  }
  EXPECT_GT(static_cast<double>(agree), 0.9 * static_cast<double>(db.numContacts()));
  // The solid holds the whole box, up to the sensor's noise.
  const ConvexHull hull(db.geometry.hull_vertices, "hull");
  for (const Eigen::Vector3d& corner : box.corners()) EXPECT_GE(hull.depth(corner), -3 * sigma);
  // Every contact lies on the solid's surface, where a finger closing on
  // it touches it (the noisy points' hull lies outside their mean).
  double deepest = 0.0;
  for (std::size_t c = 0; c < db.numContacts(); ++c)
    deepest = std::max(
        deepest, std::abs(hull.depth(db.positions.row(static_cast<Eigen::Index>(c)).transpose())));
  EXPECT_LT(deepest, 1e-4);
  EXPECT_TRUE(db.geometry.closed);
  EXPECT_EQ(db.geometry.convex_parts.size(), 1u);
  EXPECT_FALSE(r.warnings.empty());  // says the shape is a stand-in
}

TEST(PartialView, TheSensorsNormalsAreKeptTurnedTowardsTheCamera) {
  const View view = viewOf(Box{}, kEye, 0.001, 0.0);
  const Vertices inward = -view.normals;  // either sign is accepted
  const db::ObjectDatabase db = boxDatabase(view, &inward, /*smoothing=*/0.0).database;
  for (std::size_t c = 0; c < db.numContacts(); ++c) {
    const Eigen::Vector3d p = db.positions.row(static_cast<Eigen::Index>(c)).transpose();
    Eigen::Index nearest = 0;
    (view.points.rowwise() - p.transpose()).rowwise().norm().minCoeff(&nearest);
    EXPECT_LT((db.normals.row(static_cast<Eigen::Index>(c)) - view.normals.row(nearest)).norm(),
              1e-9);
  }
  Vertices wrong = view.normals.topRows(3);
  EXPECT_THROW(boxDatabase(view, &wrong), InvalidArgument);
  // Smoothed, each contact keeps the normal of the point it came from.
  const db::ObjectDatabase smoothed = boxDatabase(view, &inward).database;
  std::size_t kept = 0;
  for (std::size_t c = 0; c < smoothed.numContacts(); ++c) {
    const Eigen::Vector3d n = smoothed.normals.row(static_cast<Eigen::Index>(c)).transpose();
    kept += (view.normals.rowwise() - n.transpose()).rowwise().norm().minCoeff() < 1e-9 ? 1 : 0;
  }
  EXPECT_EQ(kept, smoothed.numContacts());
}

TEST(PartialView, TheViewIsRecordedInTheFile) {
  const View view = viewOf(Box{}, kEye, 0.002, 0.0);
  db::ObjectDatabase db = boxDatabase(view).database;
  db.name = "box_view";
  const test::TempDir dir;
  const auto path = dir.path() / "box_view.h5";
  db::saveObjectDatabase(db, path);
  const db::ObjectDatabase read = db::loadObjectDatabase(path);
  ASSERT_TRUE(read.partial_view.has_value());
  EXPECT_EQ(read.partial_view->viewpoints, db.partial_view->viewpoints);
  EXPECT_EQ(read.partial_view->hidden_depths, db.partial_view->hidden_depths);
  EXPECT_EQ(read.partial_view->floors, db.partial_view->floors);
  EXPECT_EQ(read.partial_view->points, db.partial_view->points);
  // A record whose views disagree in number is refused.
  db.partial_view->floors.push_back(0.0);
  EXPECT_THROW(db::saveObjectDatabase(db, path), db::DatabaseError);
  // A database from a mesh records none.
  db.partial_view.reset();
  db::saveObjectDatabase(db, path);
  EXPECT_FALSE(db::loadObjectDatabase(path).partial_view.has_value());
}

TEST(PartialView, ViewsFromTwoSidesShareOneSolidAndGiveOpposedContacts) {
  const Box box;
  const Eigen::Vector3d other(-0.5, -0.2, 0.4);
  const View front = viewOf(box, kEye, 0.001, 0.0), back = viewOf(box, other, 0.001, 0.0);
  const std::vector<SensedView> views{{front.points, std::nullopt, from(kEye)},
                                      {back.points, std::nullopt, from(other)}};
  const db::ObjectDatabase both =
      buildObjectDatabaseFromViews(views, db::BuildParameters{}, "two views").database;
  const db::ObjectDatabase one = boxDatabase(front, nullptr, ViewOptions{}.smoothing).database;
  ASSERT_EQ(both.partial_view->viewpoints.rows(), 2);
  // What both hulls hold: the box, but for its sharp corners, which the
  // smoothing rounds (by 2.3 mm here), and less than either view's hull.
  const ConvexHull solid(both.geometry.hull_vertices, "solid");
  for (const Eigen::Vector3d& corner : box.corners()) EXPECT_GE(solid.depth(corner), -0.003);
  EXPECT_LT(both.geometry.volume, 0.8 * one.geometry.volume);
  EXPECT_LT(both.geometry.volume, 1.2 * box.size.prod());
  // Contacts on both sides: some normals point each way along x.
  double most = -1.0, least = 1.0;
  for (Eigen::Index c = 0; c < both.normals.rows(); ++c) {
    most = std::max(most, both.normals(c, 0));
    least = std::min(least, both.normals(c, 0));
  }
  EXPECT_GT(most, 0.9);
  EXPECT_LT(least, -0.9);
}

TEST(PartialView, ViewsOfDifferentThingsHaveNothingInCommon) {
  const View front = viewOf(Box{}, kEye, 0.002, 0.0);
  Vertices away = front.points;
  away.col(0).array() += 1.0;  // a metre along x: another object
  const std::vector<SensedView> views{{front.points, std::nullopt, from(kEye)},
                                      {away, std::nullopt, from(kEye + Eigen::Vector3d(1, 0, 0))}};
  EXPECT_THROW(buildObjectDatabaseFromViews(views, db::BuildParameters{}, "two"), MeshError);
  // A bad option of the second view is named with its index.
  std::vector<SensedView> bad{{front.points, std::nullopt, from(kEye)},
                              {front.points, std::nullopt, from(kEye, -1.0)}};
  try {
    buildObjectDatabaseFromViews(bad, db::BuildParameters{}, "two");
    ADD_FAILURE() << "no error";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(e.field(), "views[1].hidden_depth");
  }
  EXPECT_THROW(buildObjectDatabaseFromViews({}, db::BuildParameters{}, "none"), InvalidArgument);
}

}  // namespace
}  // namespace hfts::preprocess
