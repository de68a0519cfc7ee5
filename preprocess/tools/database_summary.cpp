#include "database_summary.h"

#include <iomanip>
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
          {"distance_grid_margin", p.distance_grid_margin},
          {"convex_parts_max", p.convex_parts_max},
          {"convex_parts_tolerance", p.convex_parts_tolerance}};
}

/// The convex parts' volumes added up.
double partsVolume(const db::ObjectGeometry& g) {
  double sum = 0.0;
  for (const db::ConvexPiece& part : g.convex_parts)
    sum += solidProperties(TriangleMesh{part.vertices, part.faces}).volume;
  return sum;
}

nlohmann::json convexPartsJson(const db::ObjectGeometry& g) {
  std::size_t vertices = 0, faces = 0;
  for (const db::ConvexPiece& part : g.convex_parts) {
    vertices += static_cast<std::size_t>(part.vertices.rows());
    faces += static_cast<std::size_t>(part.faces.rows());
  }
  const double volume = partsVolume(g);
  return {{"count", g.convex_parts.size()},
          {"vertices", vertices},
          {"faces", faces},
          {"volume", volume},
          {"volume_ratio", g.volume > 0.0 ? nlohmann::json(volume / g.volume) : nullptr}};
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
  nlohmann::json views = nullptr;   // null: built from a mesh
  nlohmann::json hidden = nullptr;  // null: no space beside the solid that no camera saw free
  if (const auto& v = db.partial_view) {
    if (v->hidden_low.rows() > 0) {
      double volume = 0.0;
      for (Eigen::Index b = 0; b < v->hidden_low.rows(); ++b)
        volume += (v->hidden_high.row(b) - v->hidden_low.row(b)).prod();
      hidden = {{"boxes", v->hidden_low.rows()},
                {"voxel", v->hidden_voxel},
                {"volume", volume},
                {"min", vec3(v->hidden_low.colwise().minCoeff().transpose())},
                {"max", vec3(v->hidden_high.colwise().maxCoeff().transpose())}};
    }
    views = nlohmann::json::array();
    for (Eigen::Index i = 0; i < v->viewpoints.rows(); ++i) {
      const auto k = static_cast<std::size_t>(i);
      views.push_back({{"viewpoint", vec3(v->viewpoints.row(i).transpose())},
                       {"hidden_depth", v->hidden_depths[k]},
                       {"floor", v->floors[k]},
                       {"points", v->points[k]}});
    }
  }
  return {{"name", db.name},
          {"partial_views", views},
          {"hidden_space", hidden},
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
          {"density", db.density},
          {"mass", db.density * g.volume},
          {"closed", g.closed},
          {"center_of_mass_method", db::centerOfMassMethodName(g.center_of_mass_method)},
          {"bbox_min", vec3(g.bbox_min)},
          {"bbox_max", vec3(g.bbox_max)},
          {"hull_vertices", g.hull_vertices.rows()},
          {"hull_faces", g.hull_faces.rows()},
          {"distance_grid", distanceGridJson(g.distance_grid)},
          {"convex_parts", convexPartsJson(g)},
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
      << "mesh sha256     " << db.source_sha256 << "\n";
  if (const auto& v = db.partial_view)
    out << "partial views   " << v->viewpoints.rows()
        << ": contacts on observed points only, the solid a stand-in for the unseen side"
        << (v->hidden_low.rows() > 0 ? "; " + std::to_string(v->hidden_low.rows()) +
                                           " boxes beside it no camera saw free"
                                     : std::string())
        << "\n";
  out << "contacts        " << db.numContacts() << " kept of " << db.num_samples << " samples";
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
      << "density         " << db.density << " kg/m^3 (mass " << db.density * g.volume * 1e3
      << " g)\n"
      << "bounding box    [" << g.bbox_min.transpose() << "] .. [" << g.bbox_max.transpose()
      << "] m\n"
      << "convex hull     " << g.hull_vertices.rows() << " vertices, " << g.hull_faces.rows()
      << " triangles\n"
      << "distance grid   " << g.distance_grid.dims[0] << " x " << g.distance_grid.dims[1] << " x "
      << g.distance_grid.dims[2] << " nodes, " << 1000.0 * g.distance_grid.spacing << " mm apart, "
      << (g.distance_grid.is_signed ? "signed" : "unsigned (open mesh)") << "\n"
      << "convex parts    " << g.convex_parts.size();
  if (g.volume > 0.0) {
    std::ostringstream ratio;
    ratio << std::fixed << std::setprecision(3) << partsVolume(g) / g.volume;
    out << ", their volumes " << ratio.str() << " x the solid's";
  }
  out << "\n";
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
