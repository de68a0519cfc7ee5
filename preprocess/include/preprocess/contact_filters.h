#pragma once
// The configurable chain of contact filters.

#include <string>
#include <vector>

#include "hfts_db/object_database.h"
#include "hfts_db/triangle_bvh.h"
#include "preprocess/contact_set.h"
#include "preprocess/convex_hull.h"

namespace hfts::preprocess {

/// Names accepted in BuildParameters::filters, in their default order (what
/// each protects against and why its scale is what it is:
/// docs/preprocess.md#5-contact-filters):
///  - "curvature":  surface variation within the patch radius above
///                  max_curvature (edges, corners, creases, noise: normals
///                  a pad would not meet);
///  - "concavity":  deeper than max_hull_distance below the convex hull
///                  (pockets only a finger entering the hull could reach);
///  - "clearance":  the pad's ball resting on the contact (radius
///                  pad_radius, centre pad_radius out along the normal)
///                  cuts into the object (concave creases, grooves and
///                  gaps narrower than the pad);
///  - "neighbours": fewer than min_neighbours other contacts within the
///                  patch radius (islands and slivers; PCL
///                  RadiusOutlierRemoval).
/// The scales left 0 in BuildParameters must be resolved first
/// (resolveFilterScales).
const std::vector<std::string>& knownFilters();

/// Throws std::invalid_argument naming the first unknown or repeated filter.
void checkFilterNames(const std::vector<std::string>& names);

/// What the filters test contacts against: the object's convex hull and
/// a BVH of its surface mesh.
struct FilterGeometry {
  const ConvexHull& hull;
  const db::TriangleBvh& surface;
};

/// Applies the filters of `params.filters` in order, each to what the
/// previous left, and reports how many contacts each removed. Throws
/// std::invalid_argument for an unknown filter or a scale left unresolved.
std::vector<db::FilterReport> applyFilters(ContactSet& contacts, const db::BuildParameters& params,
                                           const FilterGeometry& geometry);

}  // namespace hfts::preprocess
