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

/// Name of the descriptor buildHandMap stores (12 values per sample).
inline constexpr const char* kHandDescriptorName = "triangle-edges-normals-12";
inline constexpr int kHandDescriptorSize = 12;

/// The grasp-posture test of the map: true when (1) every two fingertips
/// are at least `min_fingertip_distance` apart, (2) every pad normal points
/// towards the centroid of the other fingertips (angle < 90 deg), and
/// (3) the pads can squeeze: the point of the triangle spanned by the three
/// unit pad normals nearest to the origin is at most sin(atan(friction))
/// from it (exact for two opposing fingers: their friction cones can
/// cancel). Rigid-motion invariant. Both matrices are 3 x 3, one column
/// per finger; pad normals point out of the pads.
bool isGraspPosture(const Eigen::Matrix3d& positions, const Eigen::Matrix3d& padNormals,
                    const HandMapOptions& options);

/// The rigid-motion-invariant descriptor of an ordered triple (one column
/// per finger), 12 values: the edge lengths |p1-p0|, |p2-p1|, |p0-p2| (m),
/// then for each i (j = i+1, k = i+2 mod 3) normalWeight times
/// n_i.u_ij, n_i.u_ik and n_i.(u_ij x u_ik), with u the unit edge vectors.
/// The last term is signed, so mirror images differ. It is zero apart
/// exactly for rigid copies (non-degenerate triangles) and grows about
/// linearly with position (m) and normal (rad, times normalWeight) errors,
/// so close descriptors are promising starts for the alignment.
Eigen::Matrix<double, kHandDescriptorSize, 1> handDescriptor(const Eigen::Matrix3d& positions,
                                                             const Eigen::Matrix3d& padNormals,
                                                             double normalWeight);

/// Samples the hand joint space within the limits (a Halton sequence
/// shifted by the seed: even coverage, no clusters) and keeps the
/// configurations that pass isGraspPosture, until options.num_samples are
/// kept or options.max_draws were drawn. Stores
/// fingertip positions and pad normals in the palm frame and the
/// descriptors. Deterministic for the same model and options. Throws
/// std::invalid_argument for bad options, ModelError if the hand does not
/// have exactly 3 fingertips below the palm or if no draw passes.
db::HandMap buildHandMap(const robot::RobotModel& model, const HandMapOptions& options = {});

}  // namespace hfts::grasp
