#pragma once
// The configurable chain of contact filters.

#include <string>
#include <vector>

#include "hfts_db/object_database.h"
#include "preprocess/contact_set.h"
#include "preprocess/convex_hull.h"

namespace hfts::preprocess {

/// Names accepted in BuildParameters::filters, in their default order:
///  - "curvature":  surface variation within the patch radius above
///                  max_curvature (edges, corners, noise);
///  - "concavity":  deeper than max_hull_distance below the convex hull
///                  (pockets a fingertip cannot reach);
///  - "neighbours": fewer than min_neighbours other contacts within the
///                  patch radius (isolated points; PCL RadiusOutlierRemoval).
const std::vector<std::string>& knownFilters();

/// Throws std::invalid_argument naming the first unknown or repeated filter.
void checkFilterNames(const std::vector<std::string>& names);

/// Applies the filters of `params.filters` in order, each to what the
/// previous left, and reports how many contacts each removed.
std::vector<db::FilterReport> applyFilters(ContactSet& contacts, const db::BuildParameters& params,
                                           const ConvexHull& hull);

}  // namespace hfts::preprocess
