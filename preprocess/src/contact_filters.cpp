#include "preprocess/contact_filters.h"

#include <pcl/filters/radius_outlier_removal.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <functional>
#include <stdexcept>

#include "core/invalid_argument.h"

namespace hfts::preprocess {
namespace {

using Mask = std::vector<bool>;
using Filter =
    std::function<Mask(const ContactSet&, const db::BuildParameters&, const FilterGeometry&)>;

/// How far the pad's ball may cut into the surface, as a share of its
/// radius, and still count as resting on it: the smoothed normal of a
/// curved or noisy patch tilts the ball by up to acos(0.95) = 18 degrees,
/// and a scan's noise (0.1 to 0.3 mm) pokes into an 8 mm ball by 1 to 4 %.
/// Against a 90-degree crease it is no excuse: the ball reaches to
/// (1 - 0.05) of its radius from the crease.
constexpr double kClearanceSlack = 0.05;

Eigen::Vector3d row(const Vertices& m, std::size_t i) {
  return m.row(static_cast<Eigen::Index>(i)).transpose();
}

Mask curvatureFilter(const ContactSet& c, const db::BuildParameters& p, const FilterGeometry&) {
  Mask keep(c.size());
  for (std::size_t i = 0; i < c.size(); ++i)
    keep[i] = c.curvature(static_cast<Eigen::Index>(i)) <= p.max_curvature;
  return keep;
}

Mask concavityFilter(const ContactSet& c, const db::BuildParameters& p, const FilterGeometry& g) {
  Mask keep(c.size());
  for (std::size_t i = 0; i < c.size(); ++i)
    keep[i] = g.hull.isShallow(row(c.positions, i), p.max_hull_distance);
  return keep;
}

Mask clearanceFilter(const ContactSet& c, const db::BuildParameters& p, const FilterGeometry& g) {
  Mask keep(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) {
    const Eigen::Vector3d centre = row(c.positions, i) + p.pad_radius * row(c.normals, i);
    keep[i] = !g.surface.isWithin(centre, (1.0 - kClearanceSlack) * p.pad_radius);
  }
  return keep;
}

Mask neighboursFilter(const ContactSet& c, const db::BuildParameters& p, const FilterGeometry&) {
  Mask keep(c.size(), false);
  if (c.size() == 0) return keep;
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  for (Eigen::Index i = 0; i < c.positions.rows(); ++i)
    cloud->push_back(pcl::PointXYZ(static_cast<float>(c.positions(i, 0)),
                                   static_cast<float>(c.positions(i, 1)),
                                   static_cast<float>(c.positions(i, 2))));
  pcl::RadiusOutlierRemoval<pcl::PointXYZ> removal;
  removal.setInputCloud(cloud);
  removal.setRadiusSearch(p.patch_radius);
  // PCL keeps a point when its radius search, which includes the point
  // itself, finds more than this many: i.e. at least this many others.
  removal.setMinNeighborsInRadius(static_cast<int>(p.min_neighbours));
  pcl::Indices inliers;
  removal.filter(inliers);
  for (const auto i : inliers) keep[static_cast<std::size_t>(i)] = true;
  return keep;
}

const std::vector<std::pair<std::string, Filter>>& registry() {
  static const std::vector<std::pair<std::string, Filter>> filters = {
      {"curvature", curvatureFilter},
      {"concavity", concavityFilter},
      {"clearance", clearanceFilter},
      {"neighbours", neighboursFilter}};
  return filters;
}

/// Every scale a filter of the list uses must have been resolved.
void checkScales(const db::BuildParameters& p) {
  const auto uses = [&](const char* name) {
    return std::find(p.filters.begin(), p.filters.end(), name) != p.filters.end();
  };
  if ((uses("curvature") || uses("neighbours")) && !(p.patch_radius > 0.0))
    throw InvalidArgument("patch_radius", "must be resolved to a positive radius");
  if (uses("clearance") && !(p.pad_radius > 0.0))
    throw InvalidArgument("pad_radius", "must be positive");
  if (uses("neighbours") && p.min_neighbours == 0)
    throw InvalidArgument("min_neighbours", "must be resolved to at least 1");
}

const Filter& lookup(const std::string& name) {
  for (const auto& [known, filter] : registry())
    if (known == name) return filter;
  std::string list;
  for (const std::string& known : knownFilters()) list += (list.empty() ? "" : ", ") + known;
  throw InvalidArgument("filters", "unknown contact filter '" + name + "' (known: " + list + ")");
}

}  // namespace

const std::vector<std::string>& knownFilters() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const auto& entry : registry()) out.push_back(entry.first);
    return out;
  }();
  return names;
}

void checkFilterNames(const std::vector<std::string>& names) {
  for (std::size_t i = 0; i < names.size(); ++i) {
    lookup(names[i]);
    if (std::find(names.begin(), names.begin() + static_cast<std::ptrdiff_t>(i), names[i]) !=
        names.begin() + static_cast<std::ptrdiff_t>(i))
      throw InvalidArgument("filters", "contact filter '" + names[i] + "' is listed twice");
  }
}

std::vector<db::FilterReport> applyFilters(ContactSet& contacts, const db::BuildParameters& params,
                                           const FilterGeometry& geometry) {
  checkFilterNames(params.filters);
  checkScales(params);
  std::vector<db::FilterReport> reports;
  for (const std::string& name : params.filters) {
    const Mask keep = lookup(name)(contacts, params, geometry);
    const std::size_t before = contacts.size();
    contacts.keep(keep);
    reports.push_back({name, before - contacts.size()});
  }
  return reports;
}

}  // namespace hfts::preprocess
