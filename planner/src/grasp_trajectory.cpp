#include "planner/grasp_trajectory.h"

#include <algorithm>
#include <cmath>

#include "core/invalid_argument.h"

namespace hfts::planner {
namespace {

/// Blends tighter by this factor each time one collides; below the
/// smallest, the exact path.
constexpr double kTighten = 4.0;
constexpr int kTightenings = 3;

/// Too many states to hold (kMaxTrajectorySamples): the plan keeps its
/// path and goes without a trajectory.
bool tooLong(double states) {
  return !(states <= static_cast<double>(kMaxTrajectorySamples));
}

/// True when the polyline through the samples passes `check` under `rule`
/// (its queries added to `queries`).
bool collisionFree(const std::vector<TrajectoryPoint>& points, robot::CollisionChecker& checker,
                   const MotionCheck& check, robot::CertifyRule rule, std::size_t& queries) {
  std::vector<Eigen::VectorXd> line;
  line.reserve(points.size());
  for (const TrajectoryPoint& p : points) line.push_back(p.positions);
  const MotionVerdict verdict = checkMotion(checker, check, line, rule);
  queries += verdict.queries;
  return verdict.free;
}

/// `samples` but the first (the end of what comes before), times shifted
/// by `offset`, appended to `out`.
void appendAfter(std::vector<TrajectoryPoint> samples, double offset,
                 std::vector<TrajectoryPoint>& out) {
  for (std::size_t i = 1; i < samples.size(); ++i) {
    samples[i].time += offset;
    out.push_back(std::move(samples[i]));
  }
}

/// The trajectory through `path` (at rest at both ends) whose samples'
/// polyline passes `check` under `rule`, with its blends tightened until it
/// does; `closing` (when given, from the end of `path` on) appended.
/// Nothing when none passes or it would hold too many samples.
GraspTrajectory checkedTrajectory(const std::vector<Eigen::VectorXd>& path,
                                  std::vector<TrajectoryPoint> closing, double closingDuration,
                                  robot::CollisionChecker& checker, const MotionCheck& check,
                                  robot::CertifyRule rule, double rate, std::size_t& queries,
                                  double maxDeviation, double speed = 1.0) {
  const robot::RobotModel& model = checker.model();
  const Eigen::VectorXd velocities = speed * model.maxVelocities();
  const Eigen::VectorXd accelerations = speed * speed * model.maxAccelerations();
  TrajectoryOptions options;
  for (int attempt = 0; attempt <= kTightenings + 1; ++attempt) {
    const double deviation =
        attempt > kTightenings ? 0.0 : maxDeviation / std::pow(kTighten, attempt);
    if (attempt > 0 && deviation == options.max_deviation) continue;  // tried already
    options.max_deviation = deviation;
    const TimeOptimalTrajectory moving(path, velocities, accelerations, options);
    if (tooLong(moving.sampleCount(rate) + static_cast<double>(closing.size()))) return {};
    GraspTrajectory out;
    out.points = moving.sample(rate);
    if (!collisionFree(out.points, checker, check, rule, queries)) continue;
    out.closing_start = moving.duration();
    out.duration = moving.duration() + closingDuration;
    out.lift_start = out.carry_start = out.place_start = out.release_start = out.retreat_start =
        out.duration;
    out.deviation = moving.deviation();
    appendAfter(std::move(closing), out.closing_start, out.points);
    return out;
  }
  return {};
}

/// The checks every trajectory's inputs go through.
void checkInputs(const std::vector<Eigen::VectorXd>& path, const robot::RobotModel& model,
                 double rate, const char* pathNeeds) {
  if (!(rate > 0.0) || !std::isfinite(rate))
    throw InvalidArgument("trajectory_rate", "must be positive and finite");
  if (path.size() < 2) throw InvalidArgument("path", pathNeeds);
  if (model.maxAccelerations().size() == 0)
    throw robot::ModelError("robot '" + model.name() +
                            "' has no max_accelerations in its config: trajectories need them");
}

}  // namespace

GraspTrajectory graspTrajectory(const std::vector<Eigen::VectorXd>& path,
                                robot::CollisionChecker& checker, const MotionCheck& check,
                                double rate, std::size_t* queries, double maxDeviation) {
  std::size_t ownQueries = 0;
  std::size_t& counted = queries != nullptr ? *queries : ownQueries;
  const robot::RobotModel& model = checker.model();
  checkInputs(path, model, rate, "needs a pre-grasp and a grasp");
  const std::vector<Eigen::VectorXd> approach(path.begin(), path.end() - 1);
  TrajectoryOptions exact;
  exact.max_deviation = 0.0;
  const TimeOptimalTrajectory closing({path[path.size() - 2], path.back()}, model.maxVelocities(),
                                      model.maxAccelerations(), exact);
  if (tooLong(closing.sampleCount(rate))) return {};
  std::vector<TrajectoryPoint> closingSamples = closing.sample(rate);
  // The closing's fingertip depth is the grasp rule's, sampled; a proof
  // leaves it out.
  MotionCheck sampled = check;
  sampled.bound = nullptr;
  if (!collisionFree(closingSamples, checker, sampled, robot::CertifyRule::kClosing, counted) ||
      (check.certifies() &&
       !collisionFree(closingSamples, checker, check, robot::CertifyRule::kClosing, counted)))
    return {};
  return checkedTrajectory(approach, std::move(closingSamples), closing.duration(), checker, check,
                           robot::CertifyRule::kApproach, rate, counted, maxDeviation);
}

GraspTrajectory motionTrajectory(const std::vector<Eigen::VectorXd>& path,
                                 robot::CollisionChecker& checker, const MotionCheck& check,
                                 double rate, std::size_t* queries, double maxDeviation,
                                 double speed) {
  std::size_t ownQueries = 0;
  checkInputs(path, checker.model(), rate, "needs a start and a goal");
  if (!(speed > 0.0 && speed <= 1.0))
    throw InvalidArgument("speed", "must be in (0, 1], not " + std::to_string(speed));
  return checkedTrajectory(path, {}, 0.0, checker, check, robot::CertifyRule::kTransit, rate,
                           queries != nullptr ? *queries : ownQueries, maxDeviation, speed);
}

double appendTrajectory(GraspTrajectory& trajectory, const GraspTrajectory& next) {
  if (trajectory.points.empty() || next.points.empty()) return -1.0;
  const double start = trajectory.duration;
  appendAfter(next.points, start, trajectory.points);
  trajectory.duration += next.duration;
  trajectory.deviation = std::max(trajectory.deviation, next.deviation);
  return start;
}

}  // namespace hfts::planner
