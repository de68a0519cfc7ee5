#pragma once
// A 6-D convex hull specialised for grasp wrench sets (private to
// grasp_quality.cpp): beneath-beyond insertion on a triangulated hull, where every
// new facet's plane is a combination of the two planes meeting at its
// horizon ridge, so no facet ever needs a determinant. Only the part of
// the hull that decides the origin's depth is built: points go in while
// they see the facet nearest the origin, the highest first.

#include <Eigen/Core>

#include <cstddef>
#include <optional>

namespace hfts::grasp {

/// Most facets the incremental hull may create (about 200 bytes each with
/// its tables), which bounds its memory and time whatever the wrenches: the
/// worst sets of kMaxQualityWrenches found (contacts on a circle or sphere,
/// 4 x 64 edges, high friction) need 660 k facets, 0.5 s and 130 MB.
constexpr std::size_t kMaxHullFacets = std::size_t{1} << 21;

/// Smallest distance from the origin to a facet of the convex hull of the
/// columns when the origin lies strictly inside (> `tolerance` from every
/// facet), 0 when it does not or the points do not span 6 dimensions.
/// nullopt when the incremental construction meets an inconsistency from
/// rounding (the caller then falls back to Qhull). Throws InvalidArgument
/// when the hull would need more than kMaxHullFacets facets.
std::optional<double> originDepthIncremental(const Eigen::Matrix<double, 6, Eigen::Dynamic>& w);

}  // namespace hfts::grasp
