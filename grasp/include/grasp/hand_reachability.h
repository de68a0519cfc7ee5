#pragma once
// Hand reachability R(h) of the paper's Eq. (1): how well the hand alone
// (any palm pose, the hand DoF within their limits) can put its m
// fingertips (m = 2..4) onto m contacts with the pads pushing into the
// surface.
// Answered from a precomputed hand map (hfts_db/hand_map.h) through a k-d
// tree and refined locally (docs/hand_reachability.md).

#include <Eigen/Geometry>

#include <memory>
#include <optional>
#include <vector>

#include "grasp/hand_map_builder.h"
#include "hfts_db/hand_map.h"
#include "robot/robot_model.h"

namespace hfts::grasp {

/// Search settings of HandReachability::query (docs/hand_reachability.md).
/// The defaults answer in about 20 us and reach about three quarters of
/// exactly reachable triples to R < 1 mm (the rest get a small, honest
/// upper bound); thorough() reaches 99.5% in about 150 us.
struct HandQueryOptions {
  int neighbours = 8;             ///< (sample, finger order) pairs from the k-d tree, 1..256
  double search_tolerance = 6.0;  ///< neighbours may be (1 + this) times farther than the true ones
  int refined_candidates = 2;     ///< candidates tracked to the triple (best of each order first)
  int tracking_stages = 2;        ///< continuation stages from a sample to the triple
  int stage_iterations = 1;       ///< Levenberg-Marquardt iterations per stage
  int finished_candidates = 1;    ///< best tracked candidates refined further, until one reaches
  int refine_iterations = 8;      ///< iterations for each finished candidate

  /// For the final grasp: searches much wider.
  static HandQueryOptions thorough() { return {64, 3.0, 12, 3, 2, 6, 20}; }
};

/// The answer for one grasp (m contacts).
struct HandQuery {
  /// R(h) >= 0 (m): the root-mean-square over the fingers i of
  /// sqrt(|T f_i(q) - c_i|^2 + lambda^2 |R_T a_i(q) + o_i|^2) for the
  /// returned palm pose T and hand posture q; f_i, a_i fingertip and unit
  /// pad normal, c_i, o_i contact and unit OUTWARD contact normal, lambda
  /// the map's normal_weight (m). |R a + o|^2 = 2 (1 - cos) of the angle
  /// between the pad and the inward normal. The query minimises it over
  /// palm poses and grasp postures (within the limits, passing
  /// isGraspPosture) by local search, so it is always achieved by the
  /// answer and never below the true minimum; 0 means exactly reachable.
  double residual = 0.0;
  double position_error = 0.0;         ///< RMS fingertip-to-contact distance (m)
  double normal_error = 0.0;           ///< largest pad-to-inward-normal angle (rad)
  Eigen::VectorXd hand_configuration;  ///< hand DoF values (RobotModel order, within limits)
  /// Palm pose in the contacts' frame: contact frame <- palm frame.
  Eigen::Isometry3d palm_pose = Eigen::Isometry3d::Identity();
  /// finger_of_contact[c]: index into RobotModel::fingertips() of the finger on contact c.
  std::vector<int> finger_of_contact;
  std::size_t map_sample = 0;  ///< the map sample the answer was refined from
  /// Set when the hand can turn about the line through its fingertips
  /// without moving them or turning its pads: two fingertips whose pads
  /// face along that line (a parallel-jaw gripper). The line (contact
  /// frame, through the placed fingertips, unit direction); every palm pose
  /// turned about it (turnedPalm) achieves the same residual, so the turn
  /// is a free parameter of the grasp.
  std::optional<Eigen::ParametrizedLine<double, 3>> free_turn;
};

/// The answer's palm pose turned by `angle` (rad, right-handed about the
/// line's direction) about its free_turn line; the palm pose itself when
/// the answer has none.
Eigen::Isometry3d turnedPalm(const HandQuery& answer, double angle);

/// True when two answers are the same way of taking the contacts: the same
/// finger on each contact and every hand joint within `minHandDifference`
/// rad.
bool samePosture(const HandQuery& a, const HandQuery& b, double minHandDifference);

/// Answers R(h) for m-contact grasps from a hand map. Queries are const and
/// thread-safe.
class HandReachability {
 public:
  /// Throws ModelError when the map was built for another hand: different
  /// robot name, hand DoF names, limits or fingers, another descriptor, or
  /// fingertips that forward kinematics does not reproduce; DatabaseError
  /// when the map itself is invalid. Throws std::invalid_argument naming
  /// the option for options out of range.
  HandReachability(const robot::RobotModel& model, db::HandMap map, HandQueryOptions options = {});
  ~HandReachability();
  HandReachability(HandReachability&&) noexcept;
  HandReachability& operator=(HandReachability&&) noexcept;

  /// R(h) and the hand posture and palm pose achieving it for m contacts
  /// (columns, any frame, metres; m the hand's fingertips) with unit
  /// outward normals. Tries every assignment of contacts to fingers (m!).
  /// Throws std::invalid_argument naming the argument for a shape other
  /// than 3 x m, non-finite values or normals that are not unit vectors
  /// (+-1e-3).
  HandQuery query(const Eigen::Matrix3Xd& contactPositions,
                  const Eigen::Matrix3Xd& outwardContactNormals) const;

  /// Other ways of the hand to take the same contacts (the grasp's null
  /// space beyond the arm's IK branches): every candidate of the search
  /// refined to the end, those whose RMS fingertip-to-contact distance is
  /// at most `maxPositionError` (m), one per distinct finger assignment and
  /// hand posture (max joint difference >= `minHandDifference` rad), best
  /// residual first. query()'s answer is usually the first. Slower than
  /// query() (all candidates are finished). Throws like query() and
  /// std::invalid_argument for a negative tolerance.
  std::vector<HandQuery> queryAlternatives(const Eigen::Matrix3Xd& contactPositions,
                                           const Eigen::Matrix3Xd& outwardContactNormals,
                                           double maxPositionError,
                                           double minHandDifference = 0.05) const;

  const db::HandMap& map() const;
  const HandQueryOptions& options() const;
  /// The largest distance between two fingertips over the map's grasp
  /// postures (m): contacts farther apart than this are beyond the hand's
  /// span (a parallel-jaw gripper's stroke).
  double maxFingertipDistance() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hfts::grasp
