#include "database_summary.h"

#include <sstream>

namespace hfts::preprocess {
namespace {

nlohmann::json vec3(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

nlohmann::json parametersJson(const db::BuildParameters& p) {
  return {{"scale", p.scale},
          {"sample_density", p.sample_density},
          {"max_samples", p.max_samples},
          {"viewpoints", p.viewpoints},
          {"pad_radius", p.pad_radius},
          {"patch_radius", p.patch_radius},
          {"filters", p.filters},
          {"max_curvature", p.max_curvature},
          {"max_hull_distance", p.max_hull_distance},
          {"min_neighbours", p.min_neighbours},
          {"branching", p.branching},
          {"length_scale", p.length_scale},
          {"normal_weight", p.normal_weight},
          {"kmeans_iterations", p.kmeans_iterations},
          {"seed", p.seed},
          {"distance_grid_spacing", p.distance_grid_spacing},
          {"distance_grid_margin", p.distance_grid_margin}};
}

/// Where the centre of mass came from, in words.
std::string centerOfMassSource(const db::ObjectGeometry& g) {
  switch (g.center_of_mass_method) {
    case db::CenterOfMassMethod::kClosedMesh:
      return "volume centroid, closed mesh";
    case db::CenterOfMassMethod::kRepairedMesh:
      return "volume centroid of the mesh with its holes capped; not closed";
    case db::CenterOfMassMethod::kConvexHull:
      break;
  }
  return "hull centroid: the mesh bounds no volume";
}

nlohmann::json distanceGridJson(const db::DistanceGrid& grid) {
  return {{"origin", vec3(grid.origin)},
          {"spacing", grid.spacing},
          {"dims", grid.dims},
          {"signed", grid.is_signed}};
}

nlohmann::json graspabilityJson(const GraspabilityReport& r) {
  if (!r.value) return {{"robot", r.robot}, {"note", r.note}};
  return {
      {"robot", r.robot},          {"fraction", r.value->fraction()}, {"sampled", r.value->sampled},
      {"stable", r.value->stable}, {"reachable", r.value->reachable}, {"tolerance", r.tolerance}};
}

}  // namespace

nlohmann::json databaseSummaryJson(const db::ObjectDatabase& db,
                                   const GraspabilityReport& graspability) {
  nlohmann::json nodes = nlohmann::json::array();
  for (const auto& level : db.levels) nodes.push_back(level.size());
  nlohmann::json filters = nlohmann::json::array();
  for (const db::FilterReport& r : db.filter_reports)
    filters.push_back({{"name", r.name}, {"removed", r.removed}});
  const db::ObjectGeometry& g = db.geometry;
  return {{"name", db.name},
          {"format", db::kObjectFormatName},
          {"format_version", db::kObjectFormatVersion},
          {"producer", db.producer},
          {"source_mesh", db.source_mesh},
          {"source_sha256", db.source_sha256},
          {"branching", db.parameters.branching},
          {"num_contacts", db.numContacts()},
          {"num_samples", db.num_samples},
          {"nodes_per_level", nodes},
          {"filters", filters},
          {"center_of_mass", vec3(g.center_of_mass)},
          {"rho", g.rho},
          {"volume", g.volume},
          {"closed", g.closed},
          {"center_of_mass_method", db::centerOfMassMethodName(g.center_of_mass_method)},
          {"bbox_min", vec3(g.bbox_min)},
          {"bbox_max", vec3(g.bbox_max)},
          {"hull_vertices", g.hull_vertices.rows()},
          {"hull_faces", g.hull_faces.rows()},
          {"distance_grid", distanceGridJson(g.distance_grid)},
          {"parameters", parametersJson(db.parameters)},
          {"graspability", graspabilityJson(graspability)}};
}

std::string databaseSummaryText(const db::ObjectDatabase& db,
                                const GraspabilityReport& graspability) {
  const db::ObjectGeometry& g = db.geometry;
  std::ostringstream out;
  out.precision(4);
  out << "object          " << db.name << " (from " << db.source_mesh << ")\n"
      << "format          " << db::kObjectFormatName << " v" << db::kObjectFormatVersion
      << ", written by " << db.producer << "\n"
      << "mesh sha256     " << db.source_sha256 << "\n"
      << "contacts        " << db.numContacts() << " kept of " << db.num_samples << " samples";
  for (const db::FilterReport& r : db.filter_reports) out << "; " << r.name << " -" << r.removed;
  out << "\nbranching       ";
  for (std::size_t l = 0; l < db.parameters.branching.size(); ++l)
    out << (l ? "-" : "") << db.parameters.branching[l];
  out << "\nnodes per level ";
  for (std::size_t l = 0; l < db.levels.size(); ++l) out << (l ? " / " : "") << db.levels[l].size();
  out << "\ncentre of mass  [" << g.center_of_mass.transpose() << "] m (" << centerOfMassSource(g)
      << ")\n"
      << "rho             " << g.rho << " m\n"
      << "volume          " << g.volume * 1e6 << " cm^3\n"
      << "bounding box    [" << g.bbox_min.transpose() << "] .. [" << g.bbox_max.transpose()
      << "] m\n"
      << "convex hull     " << g.hull_vertices.rows() << " vertices, " << g.hull_faces.rows()
      << " triangles\n"
      << "distance grid   " << g.distance_grid.dims[0] << " x " << g.distance_grid.dims[1] << " x "
      << g.distance_grid.dims[2] << " nodes, " << 1000.0 * g.distance_grid.spacing << " mm apart, "
      << (g.distance_grid.is_signed ? "signed" : "unsigned (open mesh)") << "\n";
  out << "graspability    ";
  if (const auto& v = graspability.value) {
    out.precision(3);
    out << v->fraction() << " for " << graspability.robot << " in free space: " << v->reachable
        << " of " << v->sampled
        << " sampled leaf grasps stable and within R(h) <= " << 1000.0 * graspability.tolerance
        << " mm (" << v->stable << " stable)\n";
  } else {
    out << "unknown: " << graspability.note << "\n";
  }
  return out.str();
}

}  // namespace hfts::preprocess
