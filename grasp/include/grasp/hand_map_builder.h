#pragma once
// The offline half of hand reachability: the hand map of a robot's hand,
// sampled grasp postures with their rigid-motion-invariant descriptors
// (docs/hand_reachability.md). Built by `hfts-preprocess --hand`, stored by
// hfts_db/hand_map.h, queried by grasp/hand_reachability.h.

#include <Eigen/Core>

#include "hfts_db/hand_map.h"
#include "robot/robot_model.h"

namespace hfts::grasp {

/// Build options of a hand map, stored with it (defaults and meaning:
/// docs/hand_reachability.md).
using HandMapOptions = db::HandMapParameters;

/// The descriptor of an m-finger hand map: its name (stored with the map)
/// and size, for m = 2 ("pair-distance-normals-5"), 3
/// ("triangle-edges-normals-12", the paper's hand) and 4
/// ("quadrilateral-edges-diagonals-normals-18"). Throws InvalidArgument
/// ("fingers") for other m.
const char* handDescriptorName(int fingers);
int handDescriptorSize(int fingers);
inline constexpr int kMaxHandDescriptorSize = 18;
using HandDescriptor = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxHandDescriptorSize, 1>;

/// Fingertip positions or pad normals of m fingers, one column each (any
/// 3 x m column-major storage, no copy).
using FingerColumns = Eigen::Ref<const Eigen::Matrix3Xd>;

/// The grasp-posture test of the map: true when (1) every two fingertips
/// are at least `min_fingertip_distance` apart, (2) every pad normal points
/// towards the centroid of the other fingertips (angle < 90 deg), and
/// (3) the pads can squeeze: the point of the convex hull of the m unit
/// pad normals (a segment, triangle or tetrahedron) nearest to the origin
/// is at most sin(atan(friction)) from it (exact for two opposing fingers:
/// their friction cones can cancel). Rigid-motion invariant. Both matrices
/// are 3 x m, one column per finger, m = 2..4; pad normals point out of the
/// pads.
bool isGraspPosture(const FingerColumns& positions, const FingerColumns& padNormals,
                    const HandMapOptions& options);

/// The rigid-motion-invariant descriptor of m ordered fingertips (one
/// column per finger), handDescriptorSize(m) values. m >= 3: the lengths
/// of the cyclic edges |p1-p0|, |p2-p1|, ..., |p0-p(m-1)| (m), for m = 4
/// then the diagonals |p2-p0|, |p3-p1|, then for each finger i (j = i+1,
/// k = i+2 mod m) normalWeight times n_i.u_ij, n_i.u_ik and
/// n_i.(u_ij x u_ik), with u the unit edge vectors. m = 2: |p1-p0|, then
/// normalWeight times n_0.u, n_1.u, t_0.t_1 and u.(t_0 x t_1), with u the
/// unit vector from p0 to p1 and t_i = n_i - (n_i.u) u (the dihedral angle
/// between the pads about the line through them). The triple products are
/// signed, so mirror images differ. It is zero apart for rigid copies of
/// non-degenerate grasps and grows about linearly with position (m) and
/// normal (rad, times normalWeight) errors, so close descriptors are
/// promising starts for the alignment.
HandDescriptor handDescriptor(const FingerColumns& positions, const FingerColumns& padNormals,
                              double normalWeight);

/// The default options with the robot's own settings (its config's
/// `hand_map_normal_weight`).
HandMapOptions handMapOptions(const robot::RobotModel& model);

/// Samples the hand joint space within the limits (a Halton sequence
/// shifted by the seed: even coverage, no clusters) and keeps the
/// configurations that pass isGraspPosture, until options.num_samples are
/// kept or options.max_draws were drawn. Stores
/// fingertip positions and pad normals in the palm frame and the
/// descriptors. Deterministic for the same model and options. Throws
/// std::invalid_argument for bad options, ModelError if the hand does not
/// have 2 to 4 fingertips below the palm or if no draw passes.
db::HandMap buildHandMap(const robot::RobotModel& model, const HandMapOptions& options = {});

}  // namespace hfts::grasp
