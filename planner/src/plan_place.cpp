#include "plan_place.h"

#include <algorithm>
#include <memory>
#include <utility>

#include "carry_planning.h"
#include "physics/lift_path.h"
#include "physics/simulate_rest.h"
#include "place_goal_sampler.h"
#include "robot/kinematics.h"

namespace hfts::planner {

std::pair<std::optional<PlaceTarget>, std::string> placeTarget(const robot::Scene& scene,
                                                               const db::ObjectDatabase& object,
                                                               const PlaceGoal& goal) {
  PlaceTarget target;
  target.region = placeRegion(scene, goal);
  std::string why;
  target.faces = placeFaces(object, target.region, goal, &why);
  if (target.faces.empty()) return {std::nullopt, why};
  return {std::move(target), ""};
}

namespace {

/// A checker of the robot (not holding anything) with the object standing
/// at `pose` as the target, the grasp rule's depth the plan's.
std::unique_ptr<robot::CollisionChecker> placedChecker(const Problem& p,
                                                       const robot::Scene& obstacles,
                                                       const Eigen::Isometry3d& pose) {
  robot::Scene placed = obstacles;
  placed.target_object = p.object.name;
  placed.target_pose = pose;
  auto checker =
      std::make_unique<robot::CollisionChecker>(std::make_shared<const robot::CollisionScene>(
          p.world.collisionModel(), placed, &p.object.geometry,
          p.world.collisionMesh(p.object.name), p.world.surface(p.object.name),
          p.settings.path.clearance));
  checker->setSphereTier(p.settings.execution.sphere_tier);
  checker->setMaxPenetration(p.settings.goal.max_penetration);
  return checker;
}

/// `trajectory` run backwards in time (at rest at both ends, so it stays
/// within the limits): its closing becomes an opening at its start.
GraspTrajectory backwards(const GraspTrajectory& trajectory) {
  GraspTrajectory out = trajectory;
  out.points.assign(trajectory.points.rbegin(), trajectory.points.rend());
  for (TrajectoryPoint& point : out.points) {
    point.time = trajectory.duration - point.time;
    point.velocities = -point.velocities;
  }
  out.closing_start = trajectory.duration - trajectory.closing_start;
  return out;
}

/// The checks that finish a placement from its pre-place: the descent with
/// the object in the hand, the hand opening with the object standing there
/// (the closing rule, backwards), a straight retreat of the open hand (the
/// approach rule, backwards), the object at rest once released.
class Finisher {
 public:
  Finisher(Problem& p, const Hold& hold, const Eigen::VectorXd& pregrasp, double height,
           const ob::PlannerTerminationCondition& ptc)
      : p_(p),
        hold_(hold),
        pregrasp_(pregrasp),
        height_(height),
        ptc_(ptc),
        obstacles_(obstaclesOf(p.scene)),
        check_(p.planner->smoothing().final_check) {}

  std::optional<Placement> operator()(const Eigen::Isometry3d& pose, const grasp::RestingFace& face,
                                      const Eigen::VectorXd& prePlace, PlaceRejections& rejected) {
    const auto stop = [this] { return ptc_(); };
    Placement out;
    out.object_pose = pose;
    out.face_normal = face.normal;
    out.tipping_angle = face.tipping_angle;
    std::optional<std::vector<Eigen::VectorXd>> descent =
        heldPalmLine(hold_, obstacles_, prePlace, -Eigen::Vector3d::UnitZ(), height_, check_,
                     nullptr, nullptr, stop);
    if (!descent) {
      ++rejected.descent_blocked;
      return std::nullopt;
    }
    out.descent = std::move(*descent);

    // The object stands where it was put; the hand lets go of it.
    const std::unique_ptr<robot::CollisionChecker> checker = placedChecker(p_, obstacles_, pose);
    const Eigen::VectorXd& place = out.descent.back();
    const robot::RobotModel& robot = p_.world.robot();
    out.open = place;
    out.open.tail(robot.numHandDofs()) = pregrasp_.tail(robot.numHandDofs());
    if (!checkMotion(*checker, check_, {out.open, place}, robot::CertifyRule::kClosing, stop)
             .free) {
      ++rejected.release_blocked;
      return std::nullopt;
    }
    if (!retreat(*checker, out, stop)) {
      ++rejected.retreat_blocked;
      return std::nullopt;
    }
    out.rest = physics::simulateRest(obstacles_, p_.object, pose);
    if (!out.rest.stable) {
      ++rejected.unstable;
      return std::nullopt;
    }
    return out;
  }

 private:
  /// The first straight retreat of the open hand that is free: back along
  /// the palm's approach axis, up, or between them; checked backwards as
  /// an approach to the open hand.
  bool retreat(robot::CollisionChecker& checker, Placement& out,
               const std::function<bool()>& stop) {
    const robot::RobotModel& robot = p_.world.robot();
    const Eigen::Isometry3d palm =
        p_.scene.robot_base *
        robot::forwardKinematics(robot, out.open)[static_cast<std::size_t>(robot.palmLink())];
    const Eigen::Vector3d back = -palm.linear().col(2), up = Eigen::Vector3d::UnitZ();
    for (const auto& [name, direction] : {std::pair<const char*, Eigen::Vector3d>{"back", back},
                                          {"up", up},
                                          {"up_back", up + back}}) {
      if (stop()) return false;
      if (direction.norm() < 1e-6) continue;
      const physics::PalmLine line =
          physics::straightPalmLine(robot, p_.scene.robot_base, out.open, direction, height_);
      if (!line.problem.empty()) continue;
      std::vector<Eigen::VectorXd> approach(line.waypoints.rbegin(), line.waypoints.rend());
      if (!checkMotion(checker, check_, approach, robot::CertifyRule::kApproach, stop).free)
        continue;
      out.retreat = line.waypoints;
      out.retreat_direction = name;
      return true;
    }
    return false;
  }

  Problem& p_;
  const Hold& hold_;
  const Eigen::VectorXd& pregrasp_;
  const double height_;
  const ob::PlannerTerminationCondition& ptc_;
  const robot::Scene obstacles_;
  const MotionCheck check_;
};

/// The place's trajectory: the carry, the descent, the hand opening and
/// the retreat, each at rest at its ends; `out` gets the phases' times.
GraspTrajectory placeTrajectory(const Problem& p, const Hold& hold, const Placement& placement,
                                robot::CollisionChecker& carryChecker,
                                const MotionCheck& carryCheck, double rate, PlaceOutcome& out) {
  const MotionCheck& check = p.planner->smoothing().final_check;
  const robot::Scene obstacles = obstaclesOf(p.scene);
  // Carried at the held speed, as the lift.
  const double speed = p.lift ? p.lift->held_speed : 1.0;
  GraspTrajectory trajectory =
      motionTrajectory(placement.carry, carryChecker, carryCheck, rate, &out.certificate_queries,
                       TrajectoryOptions{}.max_deviation, speed);
  const GraspTrajectory descent = liftTrajectory(hold, obstacles, LiftPath{placement.descent, ""},
                                                 check, rate, &out.certificate_queries, speed);
  // The opening and the retreat: a grasp's approach and closing, backwards.
  std::vector<Eigen::VectorXd> approach(placement.retreat.rbegin(), placement.retreat.rend());
  approach.push_back(placement.descent.back());
  const std::unique_ptr<robot::CollisionChecker> checker =
      placedChecker(p, obstacles, placement.object_pose);
  const GraspTrajectory release =
      backwards(graspTrajectory(approach, *checker, check, rate, &out.certificate_queries));
  out.descent_start = appendTrajectory(trajectory, descent);
  out.release_start = appendTrajectory(trajectory, release);
  // Any part whose samples could not be made free leaves no trajectory.
  if (out.descent_start < 0.0 || out.release_start < 0.0) return {};
  out.retreat_start = out.release_start + release.closing_start;
  return trajectory;
}

}  // namespace

PlaceOutcome planPlace(Problem& p, const PlaceTarget& target, PlaceSearch search, const Hold& hold,
                       const Eigen::VectorXd& pregrasp, const Eigen::VectorXd& grasp,
                       const LiftPath& lift, double rate,
                       const ob::PlannerTerminationCondition& ptc) {
  PlaceOutcome out;
  const double height = p.lift ? p.lift->height : LiftOptions{}.height;
  // The carry: the robot holding the object, its hand fixed as it closed.
  CarryPlanning carry(p, hold, grasp, p.settings.path.clearance);
  robot::CollisionChecker& checker = carry.checker();
  const Eigen::VectorXd& start = lift.path.back();
  robot::CollisionPair pair;
  if (checker.inCollision(start, &pair)) {
    out.why = "at the lift's end, " + pair.first + " is within the clearance of " + pair.second;
    return out;
  }

  Finisher finish(p, hold, pregrasp, height, ptc);
  PlaceSamplingContext context;
  context.region = &target.region;
  context.faces = &target.faces;
  context.center_of_mass = p.object.geometry.center_of_mass;
  context.object_in_palm = hold.object_in_palm;
  context.height = height;
  context.ik = &carry.world().ik();
  context.checker = &checker;
  context.rng = &carry.planner().rng();
  context.robot_base = p.scene.robot_base;
  context.start = start;
  context.finish = std::ref(finish);
  std::unique_ptr<PlacementSampler> sampler;
  if (search == PlaceSearch::kCoupled)
    sampler = std::make_unique<HierarchicalPlaceSampler>(context, p.goals.coupled);
  else
    sampler = std::make_unique<DecoupledPlaceSampler>(context);

  const std::optional<std::vector<Eigen::VectorXd>> path = carry.solve(start, *sampler, ptc);
  out.rejected = sampler->rejections();
  out.iterations = carry.planner().statistics().iterations;
  out.goal_sampling_calls = sampler->statistics().calls;
  out.collision_checks = checker.checkCount();
  const Placement* placed = path ? sampler->placementOf(path->back()) : nullptr;
  if (placed == nullptr) {
    const std::uint64_t goals = sampler->statistics().valid_goals;
    out.why = goals == 0
                  ? "no placement on '" + target.region.support +
                        "' could be reached, put down, released and left (" +
                        std::to_string(out.rejected.total()) + " tried) within the time limit"
                  : "no carry to any of the " + std::to_string(goals) +
                        " placements found within the time limit";
    return out;
  }
  out.placement = *placed;
  out.placement->carry = *path;
  if (rate > 0.0 && p.world.robot().maxAccelerations().size() > 0)
    out.trajectory = placeTrajectory(p, hold, *out.placement, checker,
                                     carry.planner().smoothing().final_check, rate, out);
  return out;
}

}  // namespace hfts::planner
