#include "robot/sensed_scene.h"

#include <fcl/narrowphase/distance.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "core/invalid_argument.h"
#include "fcl_query.h"
#include "robot/kinematics.h"

namespace hfts::robot {
namespace {

/// `scene` with each cloud obstacle's voxels that `remove(obstacle, i, j,
/// k)` names taken out (a cloud left empty goes); untouched clouds shared.
Scene carved(const Scene& scene,
             const std::function<bool(const Obstacle&, int, int, int)>& remove) {
  if (std::none_of(scene.obstacles.begin(), scene.obstacles.end(),
                   [](const Obstacle& o) { return o.type == Obstacle::Type::kPoints; }))
    return scene;
  Scene out = scene;
  for (Obstacle& o : out.obstacles) {
    if (o.type != Obstacle::Type::kPoints) continue;
    VoxelCloud kept =
        withoutVoxels(*o.cloud, [&](int i, int j, int k) { return remove(o, i, j, k); });
    if (kept.occupied_count == o.cloud->occupied_count) continue;
    auto cloud = std::make_shared<const VoxelCloud>(std::move(kept));
    o.mesh = cloud->mesh;
    o.distance_grid = std::shared_ptr<const db::DistanceGrid>(cloud, &cloud->distances);
    o.cloud = std::move(cloud);
  }
  out.obstacles.erase(std::remove_if(out.obstacles.begin(), out.obstacles.end(),
                                     [](const Obstacle& o) {
                                       return o.type == Obstacle::Type::kPoints &&
                                              o.cloud->occupied_count == 0;
                                     }),
                      out.obstacles.end());
  return out;
}

Eigen::Vector3d voxelCentre(const Obstacle& o, int i, int j, int k) {
  return Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5) * o.cloud->options.voxel;
}

std::array<int, 3> voxelOf(const Eigen::Vector3d& p, double voxel) {
  return {static_cast<int>(std::floor(p.x() / voxel)), static_cast<int>(std::floor(p.y() / voxel)),
          static_cast<int>(std::floor(p.z() / voxel))};
}

/// The index of voxel (i, j, k) in `cloud`'s block, or -1 outside it.
std::ptrdiff_t cellOf(const VoxelCloud& cloud, int i, int j, int k) {
  const int x = i - cloud.first[0], y = j - cloud.first[1], z = k - cloud.first[2];
  if (x < 0 || y < 0 || z < 0 || x >= cloud.dims[0] || y >= cloud.dims[1] || z >= cloud.dims[2])
    return -1;
  return static_cast<std::ptrdiff_t>(x) +
         static_cast<std::ptrdiff_t>(cloud.dims[0]) *
             (static_cast<std::ptrdiff_t>(y) + static_cast<std::ptrdiff_t>(cloud.dims[1]) * z);
}

/// Marks in `seen` (one byte per voxel of `target`'s block) the occupied
/// voxels of `target` (its frame) that `viewer`'s camera saw through:
/// along the ray to each of its points, up to the point less its radius
/// and half of target's voxel diagonal.
void markSeenThrough(const Obstacle& target, const Obstacle& viewer,
                     std::vector<std::uint8_t>& seen) {
  const VoxelCloud& to = *target.cloud;
  const VoxelCloud& from = *viewer.cloud;
  const double v = to.options.voxel;
  const Eigen::Isometry3d toTarget = target.pose.inverse() * viewer.pose;
  const Eigen::Vector3d eye = toTarget * *from.options.viewpoint;
  const double margin = from.options.radius + 0.5 * std::sqrt(3.0) * v;
  // Only the part of a ray within the target's voxels can meet one.
  const Eigen::Vector3d low = to.low() - Eigen::Vector3d::Constant(v);
  const Eigen::Vector3d high = to.high() + Eigen::Vector3d::Constant(v);
  const double step = v / 2;
  for (Eigen::Index p = 0; p < from.points.rows(); ++p) {
    const Eigen::Vector3d point = toTarget * Eigen::Vector3d(from.points.row(p).transpose());
    const Eigen::Vector3d ray = point - eye;
    const double length = ray.norm() - margin;
    if (!(length > 0.0)) continue;
    const Eigen::Vector3d along = ray.normalized();
    double enter = 0.0, leave = length;
    for (int a = 0; a < 3 && enter <= leave; ++a) {
      if (along[a] == 0.0) {
        if (eye[a] < low[a] || eye[a] > high[a]) leave = -1.0;
        continue;
      }
      const double t0 = (low[a] - eye[a]) / along[a], t1 = (high[a] - eye[a]) / along[a];
      enter = std::max(enter, std::min(t0, t1));
      leave = std::min(leave, std::max(t0, t1));
    }
    if (enter > leave) continue;
    // Samples half a voxel apart from the eye on, within the box; those
    // nearer a sample than its distance bound to the occupied voxels are
    // in none and skipped.
    const double end = std::min(leave + step, length);
    for (auto m = static_cast<long>(std::floor(enter / step)); m * step < end;) {
      const Eigen::Vector3d sample = eye + (m * step) * along;
      const double clear = to.distances.lowerBound(sample);
      if (clear > 0.0) {
        m += std::max(1L, static_cast<long>(std::ceil(clear / step)) - 1);
        continue;
      }
      const auto [i, j, k] = voxelOf(sample, v);
      const std::ptrdiff_t cell = cellOf(to, i, j, k);
      if (cell >= 0 && to.occupied[static_cast<std::size_t>(cell)])
        seen[static_cast<std::size_t>(cell)] = 1;
      ++m;
    }
  }
}

/// Clears in `seen` (one byte per voxel of `cloud`'s block) the voxels
/// within the cloud's radius of one of its own points.
void clearObserved(const VoxelCloud& cloud, std::vector<std::uint8_t>& seen) {
  const double v = cloud.options.voxel, r = cloud.options.radius;
  for (Eigen::Index p = 0; p < cloud.points.rows(); ++p) {
    const Eigen::Vector3d point = cloud.points.row(p).transpose();
    const auto from = voxelOf(point - Eigen::Vector3d::Constant(r), v);
    const auto to = voxelOf(point + Eigen::Vector3d::Constant(r), v);
    for (int k = from[2]; k <= to[2]; ++k)
      for (int j = from[1]; j <= to[1]; ++j)
        for (int i = from[0]; i <= to[0]; ++i) {
          const Eigen::Vector3d low = Eigen::Vector3d(i, j, k) * v;
          const Eigen::Vector3d gap =
              (low - point).cwiseMax(point - low - Eigen::Vector3d::Constant(v)).cwiseMax(0.0);
          const std::ptrdiff_t cell = cellOf(cloud, i, j, k);
          if (cell >= 0 && gap.squaredNorm() <= r * r) seen[static_cast<std::size_t>(cell)] = 0;
        }
  }
}

/// Which voxel (obstacle, absolute index) a carving takes out.
using CarveRule = std::function<bool(const Obstacle&, int, int, int)>;

/// withSeenSpaceCarved's rule; none when fewer than two clouds have
/// viewpoints.
CarveRule seenSpaceRule(const Scene& scene) {
  std::vector<const Obstacle*> views;
  for (const Obstacle& o : scene.obstacles)
    if (o.type == Obstacle::Type::kPoints && o.cloud->options.viewpoint &&
        o.cloud->points.rows() > 0)
      views.push_back(&o);
  if (views.size() < 2) return {};
  auto carve = std::make_shared<std::map<std::string, std::vector<std::uint8_t>>>();
  for (const Obstacle* target : views) {
    std::vector<std::uint8_t> seen(target->cloud->occupied.size(), 0);
    for (const Obstacle* viewer : views)
      if (viewer != target) markSeenThrough(*target, *viewer, seen);
    clearObserved(*target->cloud, seen);
    (*carve)[target->name] = std::move(seen);
  }
  return [carve](const Obstacle& o, int i, int j, int k) {
    const auto found = carve->find(o.name);
    return found != carve->end() &&
           found->second[static_cast<std::size_t>(cellOf(*o.cloud, i, j, k))];
  };
}

}  // namespace

Scene withSeenSpaceCarved(const Scene& scene) {
  const CarveRule rule = seenSpaceRule(scene);
  return rule ? carved(scene, rule) : scene;
}

namespace {

/// Whether a voxel may touch an object (its distance grid and the box of
/// its vertices): the grid cannot prove the voxel's centre (the object's
/// frame) more than half the voxel's diagonal outside it.
class ObjectTouch {
 public:
  ObjectTouch(const db::DistanceGrid& grid, const Vertices& vertices)
      : grid_(grid), low_(vertices.colwise().minCoeff()), high_(vertices.colwise().maxCoeff()) {}
  bool operator()(const Eigen::Vector3d& centre, double voxel) const {
    const double halfDiagonal = 0.5 * std::sqrt(3.0) * voxel;
    // Outside the object's box by more than the half diagonal: clear.
    if ((centre.array() < low_.array() - halfDiagonal).any() ||
        (centre.array() > high_.array() + halfDiagonal).any())
      return false;
    return grid_.lowerBound(centre) <= halfDiagonal;
  }

 private:
  const db::DistanceGrid& grid_;
  Eigen::Vector3d low_, high_;
};

/// withTargetCarved's rule; none without a grid or vertices.
CarveRule targetRule(const Scene& scene, const db::DistanceGrid& grid, const Vertices& vertices) {
  if (vertices.rows() == 0 || grid.empty()) return {};
  const Eigen::Isometry3d toTarget = scene.target_pose.inverse();
  return [touches = ObjectTouch(grid, vertices), toTarget](const Obstacle& o, int i, int j, int k) {
    return touches(toTarget * o.pose * voxelCentre(o, i, j, k), o.cloud->options.voxel);
  };
}

/// withRobotCarved's rule.
CarveRule robotRule(const Scene& scene, const RobotModel& model, const Eigen::VectorXd& q,
                    double padding) {
  const LinkPoses poses = forwardKinematics(model, q);
  struct Shape {
    fcl_query::Object object;
    Eigen::AlignedBox3d box;  ///< world frame, FCL's
  };
  auto shapes = std::make_shared<std::vector<Shape>>();
  for (std::size_t l = 0; l < model.links().size(); ++l)
    for (const CollisionShape& s : model.links()[l].shapes) {
      const Eigen::Isometry3d pose = scene.robot_base * poses[l] * s.origin;
      fcl_query::Object object(fcl_query::primitive(static_cast<int>(s.type), s.size),
                               pose.linear(), pose.translation());
      object.computeAABB();
      shapes->push_back(
          {object, Eigen::AlignedBox3d(object.getAABB().min_, object.getAABB().max_)});
    }
  return [shapes, padding](const Obstacle& o, int i, int j, int k) {
    const double reach = padding + 0.5 * std::sqrt(3.0) * o.cloud->options.voxel;
    const Eigen::Vector3d centre = o.pose * voxelCentre(o, i, j, k);
    for (const Shape& s : *shapes) {
      if (s.box.exteriorDistance(centre) > reach) continue;
      fcl_query::Object point(std::make_shared<fcl::Sphered>(1e-9), Eigen::Matrix3d::Identity(),
                              centre);
      fcl::DistanceRequestd request;
      fcl::DistanceResultd result;
      if (fcl::distance(&s.object, &point, request, result) <= reach) return true;
    }
    return false;
  };
}

}  // namespace

Scene withTargetCarved(const Scene& scene, const db::DistanceGrid& grid, const Vertices& vertices) {
  const CarveRule rule = targetRule(scene, grid, vertices);
  return rule ? carved(scene, rule) : scene;
}

std::string hiddenSideName(const std::string& target) {
  return target + ".hidden";
}

std::string hiddenSkinName(const std::string& target) {
  return target + ".hidden_skin";
}

bool isHiddenSpaceOf(const std::string& obstacle, const std::string& target) {
  return obstacle == hiddenSideName(target) || obstacle == hiddenSkinName(target);
}

namespace {

/// An obstacle of the voxels of edge `voxel` centred at `centres` (the
/// target's frame, at `pose`): exactly those voxels, no radius.
Obstacle hiddenVoxels(const std::string& name, const std::vector<Eigen::Vector3d>& centres,
                      double voxel, const Eigen::Isometry3d& pose) {
  Vertices points(static_cast<Eigen::Index>(centres.size()), 3);
  for (std::size_t i = 0; i < centres.size(); ++i)
    points.row(static_cast<Eigen::Index>(i)) = centres[i].transpose();
  CloudOptions options;
  options.voxel = voxel;
  options.radius = 0.0;
  options.shadow = 0.0;
  Obstacle o;
  o.name = name;
  o.type = Obstacle::Type::kPoints;
  o.pose = pose;
  try {
    auto cloud = std::make_shared<VoxelCloud>(voxelize(points, options));
    o.mesh = cloud->mesh;
    o.distance_grid = std::shared_ptr<const db::DistanceGrid>(cloud, &cloud->distances);
    o.cloud = std::move(cloud);
  } catch (const InvalidArgument& e) {
    throw InvalidArgument("partial_view", "the hidden space of '" + name + "': " + e.problem());
  }
  return o;
}

}  // namespace

Scene withHiddenSide(const Scene& scene, const db::ObjectDatabase& target) {
  if (!target.partial_view || target.partial_view->hidden_low.rows() == 0) return scene;
  const db::PartialView& view = *target.partial_view;
  const db::ObjectGeometry& geometry = target.geometry;
  std::optional<ObjectTouch> touches;
  if (!geometry.distance_grid.empty() && geometry.mesh_vertices.rows() > 0)
    touches.emplace(geometry.distance_grid, geometry.mesh_vertices);
  // The centre of every voxel of every box: a cloud of the same voxel and
  // no radius holds exactly the boxes.
  const double v = view.hidden_voxel;
  std::vector<Eigen::Vector3d> apart, skin;
  for (Eigen::Index b = 0; b < view.hidden_low.rows(); ++b) {
    const Eigen::Array3d first = (view.hidden_low.row(b).transpose().array() / v).round();
    const Eigen::Array3d end = (view.hidden_high.row(b).transpose().array() / v).round();
    for (double k = first.z(); k < end.z(); ++k)
      for (double j = first.y(); j < end.y(); ++j)
        for (double i = first.x(); i < end.x(); ++i) {
          const Eigen::Vector3d centre(v * (i + 0.5), v * (j + 0.5), v * (k + 0.5));
          (touches && (*touches)(centre, v) ? skin : apart).push_back(centre);
        }
  }
  Scene out = scene;
  for (const auto& [name, centres] : {std::pair{hiddenSideName(scene.target_object), &apart},
                                      std::pair{hiddenSkinName(scene.target_object), &skin}})
    if (!centres->empty())
      out.obstacles.push_back(hiddenVoxels(name, *centres, v, scene.target_pose));
  return out;
}

Scene heldScene(Scene scene) {
  const std::string skin = hiddenSkinName(scene.target_object);
  scene.obstacles.erase(std::remove_if(scene.obstacles.begin(), scene.obstacles.end(),
                                       [&](const Obstacle& o) { return o.name == skin; }),
                        scene.obstacles.end());
  scene.target_object.clear();
  return scene;
}

Scene withRobotCarved(const Scene& scene, const RobotModel& model, const Eigen::VectorXd& q,
                      double padding) {
  if (std::none_of(scene.obstacles.begin(), scene.obstacles.end(),
                   [](const Obstacle& o) { return o.type == Obstacle::Type::kPoints; }))
    return scene;
  return carved(scene, robotRule(scene, model, q, padding));
}

Scene asPlannerSees(const Scene& scene, const db::ObjectDatabase& target, const RobotModel& model,
                    const Eigen::VectorXd& start) {
  // The carvings of withSeenSpaceCarved, withTargetCarved (not of the
  // hidden space, which may touch the object) and withRobotCarved, as one:
  // each cloud rebuilt once.
  const Scene withHidden = withHiddenSide(scene, target);
  if (std::none_of(withHidden.obstacles.begin(), withHidden.obstacles.end(),
                   [](const Obstacle& o) { return o.type == Obstacle::Type::kPoints; }))
    return withHidden;
  const CarveRule seen = seenSpaceRule(scene);
  const CarveRule touching =
      targetRule(scene, target.geometry.distance_grid, target.geometry.mesh_vertices);
  const CarveRule robot = robotRule(withHidden, model, start, kSelfFilterPadding);
  return carved(withHidden, [&](const Obstacle& o, int i, int j, int k) {
    if (!isHiddenSpaceOf(o.name, scene.target_object) &&
        ((seen && seen(o, i, j, k)) || (touching && touching(o, i, j, k))))
      return true;
    return robot(o, i, j, k);
  });
}

}  // namespace hfts::robot
