#include "planner/place_goal.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/invalid_argument.h"

namespace hfts::planner {
namespace {

/// A support's top is level when its box's z axis is within this of up
/// (cos of 0.5 degrees).
constexpr double kLevel = 0.99996;
/// A resting face stands the object upright when its normal is within 2
/// degrees of the object's -z.
constexpr double kUpright = 0.99939;
/// Yaws tried when asking whether a face fits on a top.
constexpr int kFitYaws = 72;

std::string metres(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", value);
  return text;
}

/// The face's contact polygon at `pose`, in the region's frame.
Eigen::Matrix3Xd polygonIn(const PlaceRegion& region, const grasp::RestingFace& face,
                           const Eigen::Isometry3d& pose) {
  return (region.frame.inverse() * pose) * face.polygon;
}

}  // namespace

PlaceRegion placeRegion(const robot::Scene& scene, const PlaceGoal& goal) {
  const robot::Obstacle* support = scene.obstacle(goal.on);
  if (support == nullptr) {
    std::string names;
    for (const robot::Obstacle& o : scene.obstacles) names += (names.empty() ? "" : ", ") + o.name;
    throw InvalidArgument("place.on", "scene '" + scene.name + "' has no obstacle '" + goal.on +
                                          "' (its obstacles: " + names + ")");
  }
  if (support->type != robot::Obstacle::Type::kBox)
    throw InvalidArgument("place.on", "'" + goal.on +
                                          "' is not a box: only a box's level top is a place "
                                          "region");
  const Eigen::Matrix3d rotation = support->pose.linear();
  if (rotation.col(2).z() < kLevel)
    throw InvalidArgument("place.on",
                          "the top of '" + goal.on + "' is not level (tilted " +
                              metres(std::acos(std::min(1.0, rotation.col(2).z())) * 180.0 / M_PI) +
                              " degrees)");
  PlaceRegion region;
  region.support = goal.on;
  region.frame.linear() = rotation;
  region.frame.translation() =
      support->pose.translation() + rotation.col(2) * (support->size.z() / 2.0);
  region.half_extents = support->size.head<2>() / 2.0;
  if (goal.area) {
    const Eigen::AlignedBox2d& area = *goal.area;
    if (!area.min().allFinite() || !area.max().allFinite() || area.isEmpty() ||
        (area.max() - area.min()).minCoeff() <= 0.0)
      throw InvalidArgument("place.area", "must be a finite rectangle with min < max");
    // The top face's bounding box in the world.
    Eigen::AlignedBox2d top;
    for (const double sx : {-1.0, 1.0})
      for (const double sy : {-1.0, 1.0})
        top.extend((region.frame * Eigen::Vector3d(sx * region.half_extents.x(),
                                                   sy * region.half_extents.y(), 0.0))
                       .head<2>());
    if (!top.intersects(area))
      throw InvalidArgument("place.area", "lies off the top of '" + goal.on + "'");
    region.area = area;
  }
  return region;
}

std::vector<grasp::RestingFace> placeFaces(const db::ObjectDatabase& object,
                                           const PlaceRegion& region, const PlaceGoal& goal,
                                           std::string* why) {
  const auto fail = [&](const std::string& text) {
    if (why != nullptr) *why = text;
    return std::vector<grasp::RestingFace>{};
  };
  std::vector<grasp::RestingFace> faces = grasp::stablePlacements(object.geometry);
  if (faces.empty())
    return fail("'" + object.name + "' rests stably on no face (it rolls or tips over)");
  if (goal.upright) {
    const std::size_t stable = faces.size();
    faces.erase(
        std::remove_if(faces.begin(), faces.end(),
                       [](const grasp::RestingFace& f) { return -f.normal.z() < kUpright; }),
        faces.end());
    if (faces.empty())
      return fail("'" + object.name + "' stands upright on none of its " + std::to_string(stable) +
                  " stable faces");
  }
  const std::size_t allowed = faces.size();
  const Eigen::Vector2d centre = region.frame.translation().head<2>();
  const auto fitsNowhere = [&](const grasp::RestingFace& face) {
    for (int k = 0; k < kFitYaws; ++k) {
      const double yaw = 2.0 * M_PI * k / kFitYaws;
      const Eigen::Isometry3d pose = grasp::restingPose(
          face, object.geometry.center_of_mass, centre, yaw, region.frame.translation().z());
      const Eigen::Matrix3Xd corners = polygonIn(region, face, pose);
      const Eigen::Vector2d extent =
          corners.topRows<2>().rowwise().maxCoeff() - corners.topRows<2>().rowwise().minCoeff();
      if ((extent.array() <= 2.0 * region.half_extents.array()).all()) return false;
    }
    return true;
  };
  faces.erase(std::remove_if(faces.begin(), faces.end(), fitsNowhere), faces.end());
  if (faces.empty())
    return fail("none of the " + std::to_string(allowed) + " ways '" + object.name +
                "' rests fits on '" + region.support + "' (top " +
                metres(2.0 * region.half_extents.x()) + " x " +
                metres(2.0 * region.half_extents.y()) + " m)");
  return faces;
}

bool supported(const PlaceRegion& region, const grasp::RestingFace& face,
               const Eigen::Vector3d& centerOfMass, const Eigen::Isometry3d& pose) {
  const Eigen::Matrix3Xd corners = polygonIn(region, face, pose);
  constexpr double kSlack = 1e-9;
  for (Eigen::Index c = 0; c < corners.cols(); ++c)
    if (std::abs(corners(0, c)) > region.half_extents.x() + kSlack ||
        std::abs(corners(1, c)) > region.half_extents.y() + kSlack)
      return false;
  return !region.area || region.area->contains((pose * centerOfMass).head<2>());
}

std::optional<Eigen::Isometry3d> samplePlacement(const PlaceRegion& region,
                                                 const std::vector<grasp::RestingFace>& faces,
                                                 const Eigen::Vector3d& centerOfMass,
                                                 std::mt19937_64& rng, int tries) {
  if (faces.empty()) return std::nullopt;
  std::uniform_int_distribution<std::size_t> pick(0, faces.size() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double top = region.frame.translation().z() + robot::kRestingClearance;
  for (int t = 0; t < tries; ++t) {
    const grasp::RestingFace& face = faces[pick(rng)];
    Eigen::Vector2d xy;
    if (region.area) {
      const Eigen::Vector2d low = region.area->min(), high = region.area->max();
      xy = low + Eigen::Vector2d(unit(rng), unit(rng)).cwiseProduct(high - low);
    } else {
      const Eigen::Vector2d local = Eigen::Vector2d(2.0 * unit(rng) - 1.0, 2.0 * unit(rng) - 1.0)
                                        .cwiseProduct(region.half_extents);
      xy = (region.frame * Eigen::Vector3d(local.x(), local.y(), 0.0)).head<2>();
    }
    const double yaw = 2.0 * M_PI * unit(rng) - M_PI;
    const Eigen::Isometry3d pose = grasp::restingPose(face, centerOfMass, xy, yaw, top);
    if (supported(region, face, centerOfMass, pose)) return pose;
  }
  return std::nullopt;
}

}  // namespace hfts::planner
