#pragma once
// A 6-D convex hull specialised for grasp wrench sets (private to
// grasp_quality.cpp): beneath-beyond insertion on a triangulated hull, where every
// new facet's plane is a combination of the two planes meeting at its
// horizon ridge, so no facet ever needs a determinant. Only the part of
// the hull that decides the origin's depth is built: points go in while
// they see the facet nearest the origin, the highest first.

#include <Eigen/Core>

#include <optional>

namespace hfts::grasp {

/// Smallest distance from the origin to a facet of the convex hull of the
/// columns when the origin lies strictly inside (> `tolerance` from every
/// facet), 0 when it does not or the points do not span 6 dimensions.
/// nullopt when the incremental construction meets an inconsistency from
/// rounding (the caller then falls back to Qhull).
std::optional<double> originDepthIncremental(const Eigen::Matrix<double, 6, Eigen::Dynamic>& w);

}  // namespace hfts::grasp
