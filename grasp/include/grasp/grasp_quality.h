#pragma once
// The Ferrari-Canny L1 grasp quality (epsilon), the Q(h) of the paper's
// Eq. (1). Conventions fixed in docs/grasp_quality.md: inward normals,
// K-edge friction cones with normal component 1, torques about the centre
// of mass scaled by 1/rho; hard-finger (point) contacts, or soft-finger
// contacts that also resist a torque about their normal.

#include <Eigen/Core>

#include <stdexcept>
#include <vector>

namespace hfts::grasp {

/// Most wrenches (contacts x cone edges) a request from outside may have
/// (graspQualityRequestFromJson: grasp.quality, hfts-quality; the library
/// function takes any number). The cost of the 6-D hull grows steeply with
/// them: 512 wrenches of contacts on a circle take about 2 s and 250 MB,
/// 4096 over 2 min and 3.8 GB; at 256 the worst found is about 0.6 s
/// (docs/grasp_quality.md).
constexpr int kMaxQualityWrenches = 256;

/// Which way the given contact normals point.
enum class NormalDirection { kInward, kOutward };

/// A grasp quality query; defaults are the project's (mu 0.5, K 8).
struct GraspQualityRequest {
  Eigen::Matrix3Xd positions;  ///< contact points, one column each (m)
  Eigen::Matrix3Xd normals;    ///< contact normals (unit length +-1e-6)
  NormalDirection direction = NormalDirection::kInward;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< torque origin: the centre of mass
  double torque_scale = 1.0;  ///< rho: largest distance from centre to surface (m), > 0
  double friction = 0.5;      ///< mu > 0
  int cone_edges = 8;         ///< K >= 3
  /// Soft-finger contacts: gamma (m), the largest torque about the
  /// contact normal per unit normal force (a pad of radius a pressed
  /// uniformly with friction mu gives gamma = 2/3 mu a). 0: hard-finger
  /// point contacts (the paper's model).
  double torsional_friction = 0.0;
  /// Use Qhull instead of the project's incremental hull (slower; for
  /// cross-checks).
  bool use_qhull = false;
};

struct GraspQualityResult {
  /// Distance from the origin to the nearest facet of the convex hull of
  /// the contact wrenches when the origin lies strictly inside it, else 0.
  double epsilon = 0.0;
};

/// Computes epsilon from the 6-D convex hull of the wrenches: the project's
/// incremental hull, built only as far as the facet nearest the origin
/// needs (Qhull as a fallback when rounding makes it inconsistent, or for
/// more than 4096 wrenches, beyond what requests allow). Degenerate wrench sets
/// (fewer than 7 wrenches, rank below 6, coplanar contacts that cannot
/// resist every wrench, duplicates) give exactly 0 or the correct positive
/// value, never an exception. Throws std::invalid_argument naming the field
/// for mismatched sizes, no contacts, non-finite values, non-unit normals,
/// parameters out of range, or a hull that would exceed its budget of
/// 2^21 facets (about 400 MB; far beyond any request's need).
GraspQualityResult graspQuality(const GraspQualityRequest& request);

/// The primitive wrenches of every contact (6 x E*n, column-major by
/// contact; E = K, or K + 2 for soft fingers): f_k = n + mu (cos(2 pi k/K)
/// t1 + sin(2 pi k/K) t2), w = [f; (p - c) x f / rho], with inward unit
/// normals n; soft fingers add the pure torsions [n; (p - c) x n / rho +-
/// gamma n / rho] (the corners of the linearised elliptic limit surface
/// on the torsion axis, so epsilon stays conservative). The tangent t1 comes
/// from the grasp itself (the contacts' plane, centroid, centre), so
/// epsilon is invariant under rigid motions and reordering of the contacts
/// (for even K, also under the sign ambiguity of that plane's normal).
/// Exposed for tests.
Eigen::Matrix<double, 6, Eigen::Dynamic> contactWrenches(const GraspQualityRequest& request);

}  // namespace hfts::grasp
