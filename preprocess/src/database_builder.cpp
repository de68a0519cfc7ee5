#include "preprocess/database_builder.h"

#include <openssl/evp.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <memory>
#include <optional>
#include <stdexcept>

#include "core/invalid_argument.h"
#include "hfts_db/distance_grid.h"
#include "hfts_db/triangle_bvh.h"
#include "preprocess/center_of_mass.h"
#include "preprocess/contact_filters.h"
#include "preprocess/contact_set.h"
#include "preprocess/convex_decomposition.h"
#include "preprocess/convex_hull.h"
#include "preprocess/fingertip_scale.h"
#include "preprocess/hierarchy_builder.h"
#include "preprocess/object_geometry.h"
#include "preprocess/object_sidecar.h"
#include "preprocess/partial_view.h"
#include "preprocess/surface_sampler.h"

#ifndef HFTS_VERSION
#define HFTS_VERSION "unknown"
#endif

namespace hfts::preprocess {
namespace {

class Stopwatch {
 public:
  double lap() {
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(now - last_).count();
    last_ = now;
    return seconds;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

void requirePositive(double value, const char* name) {
  if (!(value > 0.0) || !std::isfinite(value))
    throw InvalidArgument(name, "must be a positive number");
}

/// The object's distance grid; a spacing too fine for the mesh is named by
/// its build parameter.
db::DistanceGrid distanceGrid(const TriangleMesh& mesh, bool closed,
                              const db::BuildParameters& params) {
  try {
    return db::buildDistanceGrid(mesh, closed,
                                 {params.distance_grid_spacing, params.distance_grid_margin});
  } catch (const InvalidArgument& e) {
    if (e.field() != "DistanceGridOptions::spacing") throw;
    throw InvalidArgument("distance_grid_spacing", e.problem());
  }
}

db::Points3 reordered(const Vertices& m, const std::vector<std::uint32_t>& order) {
  db::Points3 out(m.rows(), 3);
  for (std::size_t i = 0; i < order.size(); ++i)
    out.row(static_cast<Eigen::Index>(i)) = m.row(order[i]);
  return out;
}

/// What the mesh or the view gave: the surface the contacts lie on and
/// the solid the object is taken to be.
struct Shape {
  const TriangleMesh& mesh;
  bool closed;
  bool capped;  ///< decomposed as mesh + boundaryCaps(mesh)
  const ConvexHull& hull;
};

/// The stages every database shares once its geometry and its contacts'
/// normals are known: the filters, the hierarchy, the distance grid, the
/// convex parts; the times summed and the database validated.
void completeDatabase(ContactSet contacts, const Shape& shape, const db::BuildParameters& params,
                      BuildResult& result, Stopwatch& watch, const std::string& what) {
  db::ObjectDatabase& db = result.database;
  const db::BuildParameters& resolved = db.parameters;
  const db::TriangleBvh surface(shape.mesh);
  db.filter_reports = applyFilters(contacts, resolved, {shape.hull, surface});
  result.times.filter = watch.lap();
  if (contacts.size() == 0) {
    std::string detail;
    for (const db::FilterReport& r : db.filter_reports)
      detail += (detail.empty() ? "" : ", ") + r.name + " removed " + std::to_string(r.removed);
    throw MeshError(what + ": no contacts left after filtering " + std::to_string(db.num_samples) +
                    " samples (" + detail + ")");
  }

  HierarchyOptions options;
  options.branching = params.branching;
  options.length_scale = params.length_scale > 0.0 ? params.length_scale : db.geometry.rho;
  options.normal_weight = params.normal_weight;
  options.iterations = params.kmeans_iterations;
  options.seed = params.seed;
  const Hierarchy hierarchy = buildHierarchy(contacts.positions, contacts.normals, options);
  db.positions = reordered(contacts.positions, hierarchy.order);
  db.normals = reordered(contacts.normals, hierarchy.order);
  db.curvature.resize(static_cast<Eigen::Index>(hierarchy.order.size()));
  for (std::size_t i = 0; i < hierarchy.order.size(); ++i)
    db.curvature(static_cast<Eigen::Index>(i)) = contacts.curvature(hierarchy.order[i]);
  db.levels = hierarchy.levels;
  result.times.hierarchy = watch.lap();
  db.geometry.distance_grid = distanceGrid(shape.mesh, shape.closed, params);
  result.times.distance_grid = watch.lap();
  db.geometry.convex_parts =
      decomposeConvex(
          shape.capped ? withCaps(shape.mesh, boundaryCaps(shape.mesh).caps) : shape.mesh,
          shape.closed || shape.capped, {params.convex_parts_max, params.convex_parts_tolerance},
          what)
          .parts;
  result.times.convex_parts = watch.lap();
  result.times.total = result.times.load + result.times.sample + result.times.normals +
                       result.times.filter + result.times.hierarchy + result.times.distance_grid +
                       result.times.convex_parts;
  db::validateObjectDatabase(db, what);
}

}  // namespace

std::string producerName() {
  return std::string("hfts-preprocess ") + HFTS_VERSION;
}

void checkBuildParameters(const db::BuildParameters& p) {
  requirePositive(p.scale, "scale");
  requirePositive(p.sample_density, "sample_density");
  requirePositive(p.pad_radius, "pad_radius");
  if (!(p.patch_radius >= 0.0) || !std::isfinite(p.patch_radius))
    throw InvalidArgument("patch_radius", "must be >= 0 (0 = pad_radius / 2)");
  if (p.max_samples == 0) throw InvalidArgument("max_samples", "must be at least 1");
  if (p.viewpoints < 8) throw InvalidArgument("viewpoints", "must be at least 8");
  if (!(p.max_curvature >= 0.0)) throw InvalidArgument("max_curvature", "must be >= 0");
  if (!(p.max_hull_distance >= 0.0) || !std::isfinite(p.max_hull_distance))
    throw InvalidArgument("max_hull_distance", "must be >= 0");
  if (!(p.length_scale >= 0.0) || !std::isfinite(p.length_scale))
    throw InvalidArgument("length_scale", "must be >= 0 (0 selects rho)");
  if (!(p.normal_weight >= 0.0) || !std::isfinite(p.normal_weight))
    throw InvalidArgument("normal_weight", "must be >= 0");
  if (p.branching.empty() || p.branching.size() > 16)
    throw InvalidArgument("branching", "needs 1 to 16 levels");
  for (std::uint32_t b : p.branching)
    if (b == 0) throw InvalidArgument("branching", "factors must be >= 1");
  if (!(p.distance_grid_spacing >= 0.0) || !std::isfinite(p.distance_grid_spacing))
    throw InvalidArgument("distance_grid_spacing", "must be >= 0 (0 = automatic), got " +
                                                       std::to_string(p.distance_grid_spacing));
  if (!(p.distance_grid_margin >= 0.0) || !std::isfinite(p.distance_grid_margin))
    throw InvalidArgument("distance_grid_margin",
                          "must be >= 0, got " + std::to_string(p.distance_grid_margin));
  if (p.convex_parts_max < 1 || p.convex_parts_max > db::kMaxConvexParts)
    throw InvalidArgument("convex_parts_max", "must be in 1.." +
                                                  std::to_string(db::kMaxConvexParts) + ", got " +
                                                  std::to_string(p.convex_parts_max));
  if (!(p.convex_parts_tolerance >= 0.0 && p.convex_parts_tolerance < 1.0))
    throw InvalidArgument("convex_parts_tolerance",
                          "must be in [0, 1), got " + std::to_string(p.convex_parts_tolerance));
  checkFilterNames(p.filters);
}

namespace {

/// A closed mesh with its faces wound outwards: `mesh`, or it with every
/// face turned when its signed volume is negative (faces wound inwards,
/// which would put every signed distance's inside out), with a warning.
TriangleMesh woundOutwards(const TriangleMesh& mesh, bool closed, const std::string& what,
                           std::vector<std::string>& warnings) {
  if (!closed) return mesh;
  double signedVolume = 0.0;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    const auto corner = [&](int k) -> Eigen::Vector3d {
      return mesh.vertices.row(mesh.triangles(t, k)).transpose();
    };
    signedVolume += corner(0).dot(corner(1).cross(corner(2))) / 6.0;
  }
  if (signedVolume >= 0.0) return mesh;
  TriangleMesh turned = mesh;
  turned.triangles.col(1).swap(turned.triangles.col(2));
  warnings.push_back(what + ": the faces are wound inwards (negative volume); every face was " +
                     "turned outwards");
  return turned;
}

}  // namespace

BuildResult buildObjectDatabase(const TriangleMesh& input, bool closed,
                                const db::BuildParameters& params, const std::string& what) {
  checkBuildParameters(params);
  BuildResult result;
  const TriangleMesh mesh = woundOutwards(input, closed, what, result.warnings);
  Stopwatch watch;
  const ConvexHull hull(mesh.vertices, what);
  db::ObjectDatabase& db = result.database;
  db.producer = producerName();
  const CenterOfMass com = centerOfMass(mesh, closed, hull);
  db.geometry = objectGeometry(mesh, closed, hull, com);
  if (!closed) result.warnings.push_back(describeCenterOfMass(com, what));

  const SurfaceSamples samples = sampleVisibleSurface(
      mesh, {params.sample_density, params.max_samples, params.viewpoints, params.seed});
  db.num_samples = static_cast<std::uint64_t>(samples.positions.rows());
  result.times.sample = watch.lap();
  // The scales follow the pad, the neighbour count the density really drawn.
  db.parameters =
      resolveFilterScales(params, static_cast<double>(samples.candidates) / surfaceArea(mesh));
  const db::BuildParameters& resolved = db.parameters;

  ContactSet contacts = estimateNormals(samples.positions, samples.normals, resolved.patch_radius);
  result.times.normals = watch.lap();
  // A repaired scan is decomposed as the solid its capped mesh bounds (its
  // own mesh bounds none), as its centre of mass was found.
  const bool capped = !closed && com.method == db::CenterOfMassMethod::kRepairedMesh;
  completeDatabase(std::move(contacts), {mesh, closed, capped, hull}, params, result, watch, what);
  return result;
}

BuildResult buildObjectDatabaseFromFile(const std::filesystem::path& meshPath,
                                        const db::BuildParameters& params, double density) {
  checkBuildParameters(params);
  checkDensity(density, "density");
  const ObjectSidecar sidecar = readSidecar(meshPath);
  Stopwatch watch;
  LoadedMesh loaded = loadMesh(meshPath, params.scale);
  const double loadTime = watch.lap();
  BuildResult result = buildObjectDatabase(loaded.mesh, loaded.topology.closed(), params,
                                           "mesh '" + meshPath.string() + "'");
  result.warnings.insert(result.warnings.begin(), loaded.warnings.begin(), loaded.warnings.end());
  result.times.load = loadTime;
  result.times.total += loadTime;
  db::ObjectDatabase& db = result.database;
  db.name = meshPath.stem().string();
  db.source_mesh = meshPath.filename().string();
  db.source_sha256 = sha256File(meshPath);
  db.density = sidecar.density.value_or(density);
  return result;
}

namespace {

/// One view as the builder uses it: smoothed, with the side each point was
/// seen from and the sensor's normals (zero where it gave none).
struct PreparedView {
  Vertices points, sides, normals;
};

PreparedView prepared(const SensedView& view) {
  PreparedView out;
  const Vertices& raw = view.points;
  checkViewPoints(raw);
  if (view.normals && (view.normals->rows() != raw.rows() || !view.normals->allFinite()))
    throw InvalidArgument("normals", "need one finite normal per point (" +
                                         std::to_string(raw.rows()) + "), got " +
                                         std::to_string(view.normals->rows()));
  const Vertices given = view.normals ? *view.normals : Vertices::Zero(raw.rows(), 3);
  if (view.options.smoothing > 0.0) {
    // A hull over noisy points is as rough as the noise, and so are
    // normals from them.
    SmoothedView smoothed = smoothView(raw, view.options.viewpoint, view.options.smoothing);
    out.points = std::move(smoothed.points);
    out.sides = std::move(smoothed.normals);
    out.normals.resize(out.points.rows(), 3);
    for (std::size_t i = 0; i < smoothed.source.size(); ++i)
      out.normals.row(static_cast<Eigen::Index>(i)) = given.row(smoothed.source[i]);
    return out;
  }
  out.points = raw;
  out.normals = given;
  out.sides.resize(raw.rows(), 3);
  for (Eigen::Index i = 0; i < raw.rows(); ++i)
    out.sides.row(i) = (view.options.viewpoint - raw.row(i).transpose()).normalized().transpose();
  return out;
}

/// `rows` appended to `all`.
void append(Vertices& all, const Vertices& rows) {
  const Eigen::Index before = all.rows();
  all.conservativeResize(before + rows.rows(), 3);
  all.bottomRows(rows.rows()) = rows;
}

/// The carving of the views' depth images (carveViews) when every view
/// has one; its occlusions as warnings.
std::optional<Carving> carvedViews(const std::vector<SensedView>& views, const std::string& what,
                                   std::vector<std::string>& warnings) {
  if (std::any_of(views.begin(), views.end(), [](const SensedView& v) { return !v.depth; }))
    return std::nullopt;
  std::vector<DepthEvidence> images;
  Vertices points(0, 3);
  double reach = views.front().options.hidden_depth;
  for (const SensedView& view : views) {
    images.push_back(*view.depth);
    checkViewPoints(view.points);
    append(points, view.points);
    if (view.options.hidden_depth <= 0.0)
      reach = std::max(
          reach, (view.points.colwise().maxCoeff() - view.points.colwise().minCoeff()).maxCoeff());
  }
  Carving carving = carveViews(images, points, reach, views.front().options.floor);
  bool hidden = false;
  for (std::size_t v = 0; v < views.size(); ++v)
    if (static_cast<double>(carving.occluded[v]) >
        kOccludedOutline * static_cast<double>(carving.outline[v])) {
      hidden = true;
      warnings.push_back(what + ": view " + std::to_string(v) + ": " +
                         std::to_string(carving.occluded[v]) + " of the " +
                         std::to_string(carving.outline[v]) +
                         " pixels of the object's outline border a nearer surface, an unseen " +
                         "pixel or the image's edge: part of it may be hidden there");
    }
  if (hidden && views.front().options.hidden_depth <= 0.0 && reach < kOccludedReach) {
    // What is seen of a hidden object bounds nothing: carve again with the
    // assumed size.
    carving = carveViews(images, points, kOccludedReach, views.front().options.floor);
    warnings.push_back(what + ": the solid holds what may lie hidden up to " +
                       std::to_string(kOccludedReach) +
                       " m beyond the observed points (--hidden-depth to bound it)");
  }
  if (views.front().options.floor)
    warnings.push_back(what +
                       ": carved above the floor given, z = " + std::to_string(carving.floor));
  else if (carving.floor_fitted)
    warnings.push_back(what + ": carved above the support plane seen under the object, z = " +
                       std::to_string(carving.floor) + " (--floor to give it)");
  else
    warnings.push_back(what + ": no support plane seen under the object; carved above its " +
                       "lowest observed point, z = " + std::to_string(carving.floor) +
                       " (--floor to give it)");
  warnings.push_back(what + ": " + std::to_string(carving.centres.rows()) + " voxels of " +
                     std::to_string(carving.voxel) + " m no camera saw free");
  return carving;
}

/// The voxels the cameras could not see free outside `solid`, as boxes.
std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> carvedOutside(const ConvexHull& solid,
                                                                       const Carving& carving) {
  std::vector<Eigen::Index> outside;
  for (Eigen::Index i = 0; i < carving.centres.rows(); ++i)
    if (solid.depth(carving.centres.row(i).transpose()) < 0.0) outside.push_back(i);
  Vertices centres(static_cast<Eigen::Index>(outside.size()), 3);
  for (std::size_t i = 0; i < outside.size(); ++i)
    centres.row(static_cast<Eigen::Index>(i)) = carving.centres.row(outside[i]);
  return mergedVoxels(centres, carving.voxel);
}

/// What the hulls of `corners` have in common (only those `use` marks, all
/// when it is empty); none when none is used. Throws MeshError when they
/// have nothing in common.
std::optional<ConvexHull> commonSolid(const std::vector<Vertices>& corners,
                                      const std::vector<bool>& use, const std::string& what) {
  std::optional<ConvexHull> solid;
  for (std::size_t v = 0; v < corners.size(); ++v) {
    if (!use.empty() && !use[v]) continue;
    ConvexHull hull(corners[v], what);
    if (!solid) {
      solid.emplace(std::move(hull));
      continue;
    }
    const Vertices common = intersectionCorners(*solid, hull);
    if (common.rows() < 4)
      throw MeshError(what + ": the solids of views 0 to " + std::to_string(v) +
                      " have nothing in common (views of one object? viewpoints right?)");
    solid.emplace(common, what + ": the solid the views have in common");
  }
  return solid;
}

/// `solid` with every corner within kFootHeight above `floor` also put on
/// it: the object stands on the floor, but its foot is where the views
/// see least (pixels mixed with the support, the smoothing, shadows cut
/// short by the points they start from), and a solid whose foot is cut
/// away on one side tips over in physics. The solid only grows.
ConvexHull standingOnFloor(const ConvexHull& solid, double floor, const std::string& what) {
  const db::Points3& corners = solid.vertices();
  Vertices grown(2 * corners.rows(), 3);
  grown.topRows(corners.rows()) = corners;
  Eigen::Index count = corners.rows();
  for (Eigen::Index v = 0; v < corners.rows(); ++v)
    if (corners(v, 2) > floor && corners(v, 2) <= floor + kFootHeight)
      grown.row(count++) << corners(v, 0), corners(v, 1), floor;
  grown.conservativeResize(count, 3);
  return ConvexHull(grown, what + ": the solid standing on the floor");
}

/// `p`, inside `solid` or on it, moved out along the nearest facet's normal
/// onto that facet's plane: where a fingertip closing on the solid meets it.
Eigen::Vector3d ontoSurface(const ConvexHull& solid, const Eigen::Vector3d& p) {
  Eigen::Index nearest = 0;
  const double height =
      (solid.planes().leftCols<3>() * p + solid.planes().col(3)).maxCoeff(&nearest);
  return p - height * solid.planes().row(nearest).head<3>().transpose();
}

/// How deep `p` lies in the boxes (0 outside all of them).
double boxDepth(const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& boxes,
                const Eigen::Vector3d& p) {
  double deepest = 0.0;
  for (const auto& [low, high] : boxes)
    deepest = std::max(deepest, std::min((p - low).minCoeff(), (high - p).minCoeff()));
  return deepest;
}

}  // namespace

BuildResult buildObjectDatabaseFromViews(const std::vector<SensedView>& views,
                                         const db::BuildParameters& params,
                                         const std::string& what) {
  checkBuildParameters(params);
  if (views.empty()) throw InvalidArgument("views", "needs at least one view");
  BuildResult result;
  Stopwatch watch;
  db::ObjectDatabase& db = result.database;
  db.producer = producerName();
  db::PartialView& record = db.partial_view.emplace();
  record.viewpoints.resize(static_cast<Eigen::Index>(views.size()), 3);
  // With the depth images, where the cameras saw through first: it gives
  // the support the shadows stop at and what the shadows miss.
  const std::optional<Carving> carving = carvedViews(views, what, result.warnings);
  // The solid: each view's hull of its points and their shadows holds the
  // object unless another object hides part of it from that camera; with
  // every view's points added it holds what the others saw of that part
  // too. What the views' hulls have in common holds every observed point;
  // what it may still miss, no camera saw free: the carving's boxes below.
  Vertices observed(0, 3), sides(0, 3), normals(0, 3);
  std::vector<Vertices> shadows;
  for (std::size_t v = 0; v < views.size(); ++v) {
    const std::string field = views.size() > 1 ? "views[" + std::to_string(v) + "]." : "";
    try {
      const PreparedView view = prepared(views[v]);
      ViewOptions options = views[v].options;
      if (carving) options.floor = std::min(carving->floor, view.points.col(2).maxCoeff());
      const HiddenSide hidden = hiddenSide(view.points, options);
      shadows.push_back(hidden.corners);
      append(observed, view.points);
      append(sides, view.sides);
      append(normals, view.normals);
      record.viewpoints.row(static_cast<Eigen::Index>(v)) = views[v].options.viewpoint.transpose();
      record.hidden_depths.push_back(hidden.hidden_depth);
      record.floors.push_back(hidden.floor);
      record.points.push_back(static_cast<std::uint64_t>(views[v].points.rows()));
    } catch (const InvalidArgument& e) {
      if (field.empty()) throw;
      throw InvalidArgument(field + e.field(), e.problem());
    }
  }
  std::vector<bool> clear;
  for (std::size_t v = 0; v < views.size(); ++v)
    clear.push_back(!carving || static_cast<double>(carving->occluded[v]) <=
                                    kOccludedOutline * static_cast<double>(carving->outline[v]));
  // Views of one object: the hulls of the clear views meet by themselves.
  commonSolid(shadows, clear, what);
  for (Vertices& corners : shadows) append(corners, observed);
  std::optional<ConvexHull> solid = commonSolid(shadows, {}, what);
  // Known to stand on the floor when the floor is known: the support the
  // images show, or one given.
  if (carving || views.front().options.floor)
    solid.emplace(standingOnFloor(
        *solid, *std::min_element(record.floors.begin(), record.floors.end()), what));
  // What the cameras could not see free beyond that solid: boxes beside
  // it, kept apart (the hull of both would bury the observed surface
  // wherever an occluder stands near it); the planner keeps out of them.
  const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> boxes =
      carving ? carvedOutside(*solid, *carving)
              : std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>{};
  record.hidden_voxel = boxes.empty() ? 0.0 : carving->voxel;
  record.hidden_low.resize(static_cast<Eigen::Index>(boxes.size()), 3);
  record.hidden_high.resize(static_cast<Eigen::Index>(boxes.size()), 3);
  for (std::size_t b = 0; b < boxes.size(); ++b) {
    record.hidden_low.row(static_cast<Eigen::Index>(b)) = boxes[b].first.transpose();
    record.hidden_high.row(static_cast<Eigen::Index>(b)) = boxes[b].second.transpose();
  }
  const TriangleMesh mesh{solid->vertices(), solid->faces()};
  db.geometry = objectGeometry(mesh, true, *solid, centerOfMass(mesh, true, *solid));
  // A contact is on the solid's surface, where a finger closing on the
  // solid touches it. A point outside (one view saw where another saw
  // through: noise left at an edge, or a segmentation error) or deeper
  // inside than kMaxViewContactDepth (the inside of a mug seen from above,
  // a pocket the hull fills) is none.
  const double slack = 1e-6 * (db.geometry.bbox_max - db.geometry.bbox_min).norm();
  Eigen::Index inside = 0;
  const Eigen::Index observedCount = observed.rows();
  for (Eigen::Index i = 0; i < observed.rows(); ++i) {
    const double depth = solid->depth(observed.row(i).transpose());
    if (depth < -slack || depth > kMaxViewContactDepth) continue;
    if (boxDepth(boxes, ontoSurface(*solid, observed.row(i).transpose())) > kMaxViewContactDepth)
      continue;
    observed.row(inside) = observed.row(i);
    sides.row(inside) = sides.row(i);
    normals.row(inside) = normals.row(i);
    ++inside;
  }
  if (inside < observed.rows())
    result.warnings.push_back(what + ": " + std::to_string(observed.rows() - inside) +
                              " observed points lie outside the solid the views have in " +
                              "common or deeper in it than " +
                              std::to_string(1000.0 * kMaxViewContactDepth) +
                              " mm and are no contacts");
  observed.conservativeResize(inside, 3);
  sides.conservativeResize(inside, 3);
  normals.conservativeResize(inside, 3);
  result.warnings.push_back(
      what + ": " + std::to_string(views.size()) +
      " partial view(s); the solid is what their hulls of the points and their shadows have in " +
      "common" + ", its centre of mass that solid's centroid" +
      (carving ? "; beside it " + std::to_string(boxes.size()) +
                     " boxes of space no camera saw free, an obstacle to the planner"
               : std::string()));

  // The contacts: observed points at the sampling density, each seen from
  // a camera (the side its normal is turned to).
  const std::vector<std::uint32_t> kept =
      onePerVoxel(observed, 1.0 / std::sqrt(params.sample_density));
  Vertices positions(static_cast<Eigen::Index>(kept.size()), 3);
  Vertices keptSides(static_cast<Eigen::Index>(kept.size()), 3);
  for (std::size_t i = 0; i < kept.size(); ++i) {
    // The observed surface lies up to the noise inside the hull of the
    // noisy points: a finger closing on the solid touches it above.
    positions.row(static_cast<Eigen::Index>(i)) =
        ontoSurface(*solid, observed.row(kept[i]).transpose()).transpose();
    keptSides.row(static_cast<Eigen::Index>(i)) = sides.row(kept[i]);
  }
  db.num_samples = kept.size();
  result.times.sample = watch.lap();
  db.parameters = resolveFilterScales(params, params.sample_density);
  ContactSet contacts =
      estimateNormals(positions, keptSides, {observed, sides}, db.parameters.patch_radius);
  for (std::size_t i = 0; i < kept.size(); ++i) {  // the sensor's own, turned to the camera
    Eigen::Vector3d n = normals.row(kept[i]).transpose();
    if (n.norm() < 1e-9) continue;
    n.normalize();
    const auto row = static_cast<Eigen::Index>(i);
    if (n.dot(contacts.normals.row(row).transpose()) < 0.0) n = -n;
    contacts.normals.row(row) = n.transpose();
  }
  result.times.normals = watch.lap();
  try {
    completeDatabase(std::move(contacts), {mesh, true, false, *solid}, params, result, watch, what);
  } catch (const MeshError& e) {
    if (!carving || 4 * inside >= observedCount) throw;
    throw MeshError(
        std::string(e.what()) + "; only " + std::to_string(inside) + " of " +
        std::to_string(observedCount) +
        " observed points lie on the solid's surface: what no camera saw free (behind " +
        "other objects, beyond the views) closes around the object (more views, a " +
        "smaller --hidden-depth if the object is known to be smaller)");
  }
  return result;
}

std::string sha256File(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read '" + path.string() + "'");
  std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> ctx(EVP_MD_CTX_new(), EVP_MD_CTX_free);
  if (!ctx || EVP_DigestInit_ex(ctx.get(), EVP_sha256(), nullptr) != 1)
    throw std::runtime_error("OpenSSL: cannot start SHA-256");
  std::vector<char> buffer(1 << 16);
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    if (in.gcount() > 0)
      EVP_DigestUpdate(ctx.get(), buffer.data(), static_cast<std::size_t>(in.gcount()));
  }
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned length = 0;
  EVP_DigestFinal_ex(ctx.get(), digest, &length);
  static const char* hex = "0123456789abcdef";
  std::string out;
  for (unsigned i = 0; i < length; ++i) {
    out += hex[digest[i] >> 4];
    out += hex[digest[i] & 15];
  }
  return out;
}

}  // namespace hfts::preprocess
