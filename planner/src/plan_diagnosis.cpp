#include "plan_diagnosis.h"

#include <algorithm>

#include "robot/kinematics.h"
#include "robot/object_surface.h"

namespace hfts::planner {

namespace {

/// "a unstable, b without arm IK, ..." for the reasons that occurred.
std::string rejectionText(const GraspRejections& r) {
  std::string out;
  for (const auto& [count, what] :
       {std::pair{r.unstable, "unstable (no force closure)"},
        std::pair{r.no_arm_ik, "without arm IK solution"},
        std::pair{r.out_of_hand_reach, "out of the hand's reach"},
        std::pair{r.colliding, "colliding"},
        std::pair{r.no_pad_contact, "without every pad on the object when the hand closes"},
        std::pair{r.weak_at_contacts, "below min_epsilon where the pads touch"},
        std::pair{r.closing_blocked, "closing blocked"},
        std::pair{r.lift_blocked, "reached but without a free lift"}})
    if (count > 0) out += (out.empty() ? "" : ", ") + std::to_string(count) + " " + what;
  return out.empty() ? "none tried" : out;
}

/// How deep the robot's fingertip links at q reach into the target (m, >= 0).
double fingertipPenetration(const Problem& p, const Eigen::VectorXd& q) {
  const robot::RobotModel& robot = p.world.robot();
  const robot::ObjectSurface* surface = p.world.surface(p.object.name);
  if (surface == nullptr) return 0.0;
  const robot::LinkPoses poses = robot::forwardKinematics(robot, q);
  const Eigen::Isometry3d baseInObject = p.scene.target_pose.inverse() * p.scene.robot_base;
  double depth = 0.0;
  for (const robot::Fingertip& tip : robot.fingertips()) {
    constexpr double kTolerance = 5e-5;
    const auto link = static_cast<std::size_t>(tip.link);
    depth = std::max(
        depth, surface->linkDepth(robot.links()[link], baseInObject * poses[link], kTolerance));
  }
  return depth;
}

}  // namespace

/// Why a search found nothing.
std::pair<PlanFailure, std::string> failureOf(const SearchOutcome& found,
                                              const std::atomic<bool>* cancel) {
  const GoalSamplerStatistics& goals = found.goals;
  if (cancel != nullptr && cancel->load()) return {PlanFailure::kCancelled, "cancelled"};
  if (goals.configured_nodes > 0 && goals.kinematic_solutions == 0)
    return {PlanFailure::kObjectUnreachable,
            "none of the " + std::to_string(goals.configured_nodes) +
                " grasps tried has an arm IK solution: the object is out of reach"};
  if (goals.valid_goals == 0)
    return {PlanFailure::kNoValidGoal, "no valid goal within the time limit; of the " +
                                           std::to_string(goals.rejected.total()) +
                                           " leaf grasps tried: " + rejectionText(goals.rejected)};
  // The goals the trees reached that their goal check refused: each check
  // that ran refused one (the search failed), in its order.
  std::string dropped;
  if (const std::uint64_t reached = found.stats.dropped_goals; reached > 0) {
    const std::uint64_t physics = found.stats.physics_checks;
    const std::uint64_t lift = found.stats.rejected.lift_blocked;
    const std::uint64_t other = reached - std::min(reached, physics + lift);
    std::string why;
    for (const auto& [count, what] :
         {std::pair{other, "closing not proven free or checks cut short by the time limit"},
          std::pair{physics, "grasp did not hold in physics"}, std::pair{lift, "no free lift"}})
      if (count > 0) why += (why.empty() ? "" : ", ") + std::to_string(count) + " " + what;
    dropped = " (the trees reached " + std::to_string(reached) + " of them: " + why + ")";
  }
  return {PlanFailure::kTimeLimit, "no path to any of the " + std::to_string(goals.valid_goals) +
                                       " goals found within the time limit" + dropped};
}

PlannedGrasp describeGrasp(const Problem& p, const GoalSample& goal) {
  const robot::RobotModel& robot = p.world.robot();
  const Eigen::Isometry3d& objectPose = p.scene.target_pose;
  const grasp::GraspContacts touched = goal.closure->contacts();
  PlannedGrasp g;
  g.node = goal.node;
  g.contacts_object = touched.positions;
  g.contacts_world = objectPose * touched.positions;
  g.inward_normals_object = -touched.outward_normals;
  g.inward_normals_world = objectPose.linear() * g.inward_normals_object;
  g.epsilon = goal.contact_epsilon;
  g.planned_contacts_object = goal.contacts.positions;
  g.planned_epsilon = goal.epsilon;
  g.reachability = goal.reachability;
  g.fingertip_error = goal.fingertip_error;
  g.penetration = fingertipPenetration(p, goal.grasp);
  g.hand_configuration = goal.grasp.tail(robot.numHandDofs());
  return g;
}

PlanResult failed(PlanResult result, std::pair<PlanFailure, std::string> why) {
  result.failure = why.first;
  result.message = std::move(why.second);
  return result;
}

}  // namespace hfts::planner
