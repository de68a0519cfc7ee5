#include "planner/motion_check.h"

namespace hfts::planner {

MotionVerdict checkMotion(robot::CollisionChecker& checker, const MotionCheck& check,
                          const std::vector<Eigen::VectorXd>& waypoints, robot::CertifyRule rule,
                          const std::function<bool()>& stop) {
  MotionVerdict verdict;
  if (waypoints.empty()) return verdict;
  if (check.certifies()) {
    robot::CertifyOptions options;
    options.clearance = check.clearance;
    options.rule = rule;
    options.stop = stop;
    const robot::MotionCertificate certificate =
        robot::certifyPath(checker, *check.bound, waypoints, options);
    verdict.free = certificate.free;
    verdict.clearance = certificate.clearance;
    verdict.queries = certificate.queries;
    return verdict;
  }
  const robot::CollisionRequest request = rule == robot::CertifyRule::kClosing
                                              ? robot::CollisionRequest::grasp()
                                              : robot::CollisionRequest{};
  verdict.free = !checker.inCollision(waypoints.front(), request) &&
                 (waypoints.size() < 2 || checker.validSegments(waypoints, check.resolution,
                                                                request) == waypoints.size() - 1);
  return verdict;
}

}  // namespace hfts::planner
