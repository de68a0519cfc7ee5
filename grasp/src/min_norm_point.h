#pragma once
// The point of a polytope (the convex hull of finitely many points)
// nearest to the origin, by Wolfe's algorithm (P. Wolfe, "Finding the
// nearest point in a polytope", Math. Programming 11, 1976). Private to
// grasp/: it tells whether a set of wrenches can hold the origin at all.

#include <Eigen/Core>

namespace hfts::grasp {

/// The distance from the origin to conv(columns of `points`): 0 when the
/// origin lies in the hull (on its boundary too), else the length of the
/// nearest point, which then separates: every column p has
/// p . x >= |x|^2 for the nearest point x. Exact up to rounding (relative
/// tolerance 1e-12 of the largest squared norm). `points` needs at least
/// one column.
double distanceToHull(const Eigen::MatrixXd& points);

}  // namespace hfts::grasp
