#pragma once
// Time-optimal trajectories along a planned path under joint velocity and
// acceleration limits (docs/trajectories.md). The path is Kunz and
// Stilman's: the waypoints joined by straight segments, each corner
// rounded by a circular blend that stays within a maximum deviation of
// the corner, so the robot need not stop there. The time law along it is
// the time-optimal one for the discretised path, found by reachability
// analysis (TOPP-RA, Pham and Pham 2018): a backward pass computes the
// largest controllable path velocity at every grid point, a forward pass
// accelerates as hard as that allows. A last uniform time scale makes the
// limits hold on the continuous trajectory, not only at the grid points.

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace hfts::planner {

/// How a path is turned into a trajectory.
struct TrajectoryOptions {
  /// Largest distance (rad, plain Euclidean in joint space) a blend may
  /// leave a corner; 0 stops the robot at every corner and follows the
  /// path exactly.
  double max_deviation = 0.0025;
  /// Grid step along the path (path length, rad) of the time law. Finer
  /// is closer to time-optimal and slower to compute (linear in the path
  /// length over this).
  double path_step = 1e-3;
};

/// The most states TimeOptimalTrajectory::sample gives (about 0.4 GB for
/// a 16-DoF robot; 10,000 s at 100 per second): more is refused, not left
/// to exhaust the memory of a planning service.
inline constexpr std::size_t kMaxTrajectorySamples = 1000000;

/// One state of a trajectory.
struct TrajectoryPoint {
  double time = 0.0;  ///< from the start (s)
  Eigen::VectorXd positions, velocities, accelerations;
};

/// A trajectory through waypoints, at rest at both ends, within the
/// limits everywhere: |velocity_i| <= max_velocity_i and |acceleration_i|
/// <= max_acceleration_i at every time (to rounding).
class TimeOptimalTrajectory {
 public:
  /// Throws InvalidArgument naming the argument: no waypoints, waypoints
  /// of different sizes or with non-finite values, limits of another size
  /// or not positive and finite, options out of range (max_deviation < 0,
  /// path_step not in (0, 1]).
  TimeOptimalTrajectory(const std::vector<Eigen::VectorXd>& waypoints,
                        const Eigen::VectorXd& maxVelocity, const Eigen::VectorXd& maxAcceleration,
                        const TrajectoryOptions& options = {});

  /// Total time (s); 0 when all waypoints are the same configuration.
  double duration() const { return duration_; }

  /// The state at time t, clamped to [0, duration()].
  TrajectoryPoint at(double t) const;

  /// States every 1 / rate seconds from 0, and the final state at
  /// duration() (so the last step may be shorter). Throws InvalidArgument
  /// ("rate") unless rate is positive and finite, or when that would be
  /// more than kMaxTrajectorySamples states (sampleCount).
  std::vector<TrajectoryPoint> sample(double rate) const;

  /// How many states sample(rate) gives (a double: it may be beyond any
  /// count, or infinite). rate must be positive.
  double sampleCount(double rate) const;

  /// The largest distance of the trajectory from the waypoints' polyline
  /// (rad): at most the option max_deviation, reached in the sharpest
  /// corners.
  double deviation() const { return deviation_; }

  /// The uniform slow-down (>= 1) the last step applied so that the
  /// limits hold between the grid points: 1 + O(path_step) on blends,
  /// exactly 1 on paths without them.
  double timeScale() const { return scale_; }

  /// A straight piece or a circular blend of the path, by arc length u
  /// from its start: a line is origin + u x; an arc of `radius` around
  /// origin is origin + radius (x cos(u / radius) + y sin(u / radius)).
  struct Segment {
    bool arc = false;
    double start = 0.0, length = 0.0, radius = 0.0;
    bool stop_at_start = false;  ///< the direction jumps here: at rest
    Eigen::VectorXd origin, x, y;
  };

 private:
  /// The time law at a grid point of the path, and until the next one.
  struct Knot {
    double s = 0.0, time = 0.0;
    double speed = 0.0;         ///< path velocity ds/dt at the knot
    double acceleration = 0.0;  ///< path acceleration until the next knot
    std::size_t segment = 0;    ///< holding the path until the next knot
  };

  std::vector<Segment> segments_;
  std::vector<Knot> knots_;
  double duration_ = 0.0, deviation_ = 0.0, scale_ = 1.0;
  Eigen::VectorXd maxVelocity_, maxAcceleration_;

  void solveTimeLaw(const TrajectoryOptions& options);
  void certifyLimits();
};

}  // namespace hfts::planner
