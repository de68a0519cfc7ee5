// Reading and writing object databases (schema: docs/database.md).

#include "hdf5_file.h"
#include "hfts_db/object_database.h"

namespace hfts::db {
namespace {

using h5::Handle;

std::vector<hsize_t> shapeOf(Eigen::Index rows, Eigen::Index cols) {
  return {static_cast<hsize_t>(rows), static_cast<hsize_t>(cols)};
}

template <typename T>
std::vector<std::uint64_t> widened(const std::vector<T>& values) {
  return std::vector<std::uint64_t>(values.begin(), values.end());
}

std::uint32_t narrowed(std::uint64_t value, const std::string& name) {
  if (value > 0xffffffffULL) throw DatabaseError("attribute '" + name + "' is out of range");
  return static_cast<std::uint32_t>(value);
}

void writeParameters(hid_t file, const BuildParameters& p) {
  Handle group = h5::createGroup(file, "parameters");
  const hid_t g = group.id();
  h5::writeAttribute(g, "scale", p.scale);
  h5::writeAttribute(g, "sample_density", p.sample_density);
  h5::writeAttribute(g, "max_samples", std::uint64_t{p.max_samples});
  h5::writeAttribute(g, "viewpoints", std::uint64_t{p.viewpoints});
  h5::writeAttribute(g, "pad_radius", p.pad_radius);
  h5::writeAttribute(g, "patch_radius", p.patch_radius);
  h5::writeAttribute(g, "filters", h5::joinNames(p.filters));
  h5::writeAttribute(g, "max_curvature", p.max_curvature);
  h5::writeAttribute(g, "max_hull_distance", p.max_hull_distance);
  h5::writeAttribute(g, "min_neighbours", std::uint64_t{p.min_neighbours});
  h5::writeAttribute(g, "branching", widened(p.branching));
  h5::writeAttribute(g, "length_scale", p.length_scale);
  h5::writeAttribute(g, "normal_weight", p.normal_weight);
  h5::writeAttribute(g, "kmeans_iterations", std::uint64_t{p.kmeans_iterations});
  h5::writeAttribute(g, "seed", p.seed);
  h5::writeAttribute(g, "distance_grid_spacing", p.distance_grid_spacing);
  h5::writeAttribute(g, "distance_grid_margin", p.distance_grid_margin);
  h5::writeAttribute(g, "convex_parts_max", std::uint64_t{p.convex_parts_max});
  h5::writeAttribute(g, "convex_parts_tolerance", p.convex_parts_tolerance);
}

BuildParameters readParameters(hid_t file) {
  Handle group = h5::openGroup(file, "parameters");
  const hid_t g = group.id();
  BuildParameters p;
  p.scale = h5::readDouble(g, "scale");
  p.sample_density = h5::readDouble(g, "sample_density");
  p.max_samples = narrowed(h5::readUInt64(g, "max_samples"), "max_samples");
  p.viewpoints = narrowed(h5::readUInt64(g, "viewpoints"), "viewpoints");
  p.pad_radius = h5::readDouble(g, "pad_radius");
  p.patch_radius = h5::readDouble(g, "patch_radius");
  p.filters = h5::splitNames(h5::readStringAttribute(g, "filters"));
  p.max_curvature = h5::readDouble(g, "max_curvature");
  p.max_hull_distance = h5::readDouble(g, "max_hull_distance");
  p.min_neighbours = narrowed(h5::readUInt64(g, "min_neighbours"), "min_neighbours");
  p.branching.clear();
  for (std::uint64_t b : h5::readUInt64Attribute(g, "branching"))
    p.branching.push_back(narrowed(b, "branching"));
  p.length_scale = h5::readDouble(g, "length_scale");
  p.normal_weight = h5::readDouble(g, "normal_weight");
  p.kmeans_iterations = narrowed(h5::readUInt64(g, "kmeans_iterations"), "kmeans_iterations");
  p.seed = h5::readUInt64(g, "seed");
  p.distance_grid_spacing = h5::readDouble(g, "distance_grid_spacing");
  p.distance_grid_margin = h5::readDouble(g, "distance_grid_margin");
  p.convex_parts_max = narrowed(h5::readUInt64(g, "convex_parts_max"), "convex_parts_max");
  p.convex_parts_tolerance = h5::readDouble(g, "convex_parts_tolerance");
  return p;
}

std::vector<double> asVector(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

Eigen::Vector3d asVector3(const std::vector<double>& v, const std::string& name) {
  if (v.size() != 3) throw DatabaseError("attribute '" + name + "' must hold 3 values");
  return {v[0], v[1], v[2]};
}

void writeGeometry(hid_t file, const ObjectGeometry& geometry, double density) {
  Handle group = h5::createGroup(file, "object");
  const hid_t g = group.id();
  h5::writeAttribute(g, "density", density);
  h5::writeAttribute(g, "center_of_mass", asVector(geometry.center_of_mass));
  h5::writeAttribute(g, "rho", geometry.rho);
  h5::writeAttribute(g, "volume", geometry.volume);
  h5::writeAttribute(g, "closed", std::uint64_t{geometry.closed ? 1u : 0u});
  h5::writeAttribute(g, "center_of_mass_method",
                     centerOfMassMethodName(geometry.center_of_mass_method));
  h5::writeAttribute(g, "bbox_min", asVector(geometry.bbox_min));
  h5::writeAttribute(g, "bbox_max", asVector(geometry.bbox_max));
  const Points3& v = geometry.hull_vertices;
  const Faces3& f = geometry.hull_faces;
  h5::writeDataset(g, "hull_vertices", v.data(), shapeOf(v.rows(), 3));
  h5::writeDataset(g, "hull_faces", f.data(), shapeOf(f.rows(), 3));
  const Points3& mv = geometry.mesh_vertices;
  const Faces3& mf = geometry.mesh_triangles;
  h5::writeDataset(g, "mesh_vertices", mv.data(), shapeOf(mv.rows(), 3));
  h5::writeDataset(g, "mesh_triangles", mf.data(), shapeOf(mf.rows(), 3));
}

template <typename Matrix, typename T>
Matrix toMatrix(const h5::Array<T>& array, const std::string& name) {
  if (array.shape.size() != 2 || array.shape[1] != 3)
    throw DatabaseError("dataset '" + name + "' must have shape (n, 3)");
  Matrix m(static_cast<Eigen::Index>(array.shape[0]), 3);
  std::copy(array.data.begin(), array.data.end(), m.data());
  return m;
}

ObjectGeometry readGeometry(hid_t file, double& density) {
  Handle group = h5::openGroup(file, "object");
  const hid_t g = group.id();
  ObjectGeometry geometry;
  density = h5::readDouble(g, "density");
  geometry.center_of_mass =
      asVector3(h5::readDoubleAttribute(g, "center_of_mass"), "center_of_mass");
  geometry.rho = h5::readDouble(g, "rho");
  geometry.volume = h5::readDouble(g, "volume");
  geometry.closed = h5::readUInt64(g, "closed") != 0;
  geometry.center_of_mass_method =
      parseCenterOfMassMethod(h5::readStringAttribute(g, "center_of_mass_method"));
  geometry.bbox_min = asVector3(h5::readDoubleAttribute(g, "bbox_min"), "bbox_min");
  geometry.bbox_max = asVector3(h5::readDoubleAttribute(g, "bbox_max"), "bbox_max");
  geometry.hull_vertices = toMatrix<Points3>(h5::readDoubles(g, "hull_vertices"), "hull_vertices");
  geometry.hull_faces = toMatrix<Faces3>(h5::readUInt32s(g, "hull_faces"), "hull_faces");
  geometry.mesh_vertices = toMatrix<Points3>(h5::readDoubles(g, "mesh_vertices"), "mesh_vertices");
  geometry.mesh_triangles =
      toMatrix<Faces3>(h5::readUInt32s(g, "mesh_triangles"), "mesh_triangles");
  return geometry;
}

void writeDistanceGrid(hid_t file, const DistanceGrid& grid) {
  Handle group = h5::createGroup(file, "distance_grid");
  const hid_t g = group.id();
  h5::writeAttribute(g, "origin", asVector(grid.origin));
  h5::writeAttribute(g, "spacing", grid.spacing);
  h5::writeAttribute(g, "dims",
                     widened(std::vector<std::uint32_t>(grid.dims.begin(), grid.dims.end())));
  h5::writeAttribute(g, "signed", std::uint64_t{grid.is_signed ? 1u : 0u});
  // (nz, ny, nx): x varies fastest, as in DistanceGrid::index.
  h5::writeDataset(g, "values", grid.values.data(), {grid.dims[2], grid.dims[1], grid.dims[0]});
}

DistanceGrid readDistanceGrid(hid_t file) {
  Handle group = h5::openGroup(file, "distance_grid");
  const hid_t g = group.id();
  DistanceGrid grid;
  grid.origin = asVector3(h5::readDoubleAttribute(g, "origin"), "origin");
  grid.spacing = h5::readDouble(g, "spacing");
  const std::vector<std::uint64_t> dims = h5::readUInt64Attribute(g, "dims");
  if (dims.size() != 3) throw DatabaseError("attribute 'dims' must hold 3 values");
  for (std::size_t c = 0; c < 3; ++c) grid.dims[c] = narrowed(dims[c], "dims");
  grid.is_signed = h5::readUInt64(g, "signed") != 0;
  h5::Array<float> values = h5::readFloats(g, "values");
  const std::vector<hsize_t> shape = {grid.dims[2], grid.dims[1], grid.dims[0]};
  if (values.shape != shape)
    throw DatabaseError("dataset 'values' must have shape (dims[2], dims[1], dims[0])");
  grid.values = std::move(values.data);
  return grid;
}

/// All parts' vertices (and faces) one after the other, with the number
/// each part has: few datasets however many parts there are.
void writeConvexParts(hid_t file, const std::vector<ConvexPiece>& parts) {
  Handle group = h5::createGroup(file, "convex_parts");
  std::vector<std::uint32_t> vertexCount, faceCount;
  Eigen::Index vertices = 0, faces = 0;
  for (const ConvexPiece& part : parts) {
    vertexCount.push_back(static_cast<std::uint32_t>(part.vertices.rows()));
    faceCount.push_back(static_cast<std::uint32_t>(part.faces.rows()));
    vertices += part.vertices.rows();
    faces += part.faces.rows();
  }
  Points3 allVertices(vertices, 3);
  Faces3 allFaces(faces, 3);
  vertices = faces = 0;
  for (const ConvexPiece& part : parts) {
    allVertices.middleRows(vertices, part.vertices.rows()) = part.vertices;
    allFaces.middleRows(faces, part.faces.rows()) = part.faces;
    vertices += part.vertices.rows();
    faces += part.faces.rows();
  }
  h5::writeDataset(group.id(), "vertex_count", vertexCount.data(), {vertexCount.size()});
  h5::writeDataset(group.id(), "face_count", faceCount.data(), {faceCount.size()});
  h5::writeDataset(group.id(), "vertices", allVertices.data(), shapeOf(allVertices.rows(), 3));
  h5::writeDataset(group.id(), "faces", allFaces.data(), shapeOf(allFaces.rows(), 3));
}

std::vector<std::uint32_t> readCounts(hid_t group, const std::string& name) {
  h5::Array<std::uint32_t> counts = h5::readUInt32s(group, name);
  if (counts.shape.size() != 1) throw DatabaseError("dataset '" + name + "' must be 1-D");
  if (counts.data.size() > kMaxConvexParts)
    throw DatabaseError("dataset '" + name + "' holds more than " +
                        std::to_string(kMaxConvexParts) + " parts");
  return std::move(counts.data);
}

std::vector<ConvexPiece> readConvexParts(hid_t file) {
  Handle group = h5::openGroup(file, "convex_parts");
  const std::vector<std::uint32_t> vertexCount = readCounts(group.id(), "vertex_count");
  const std::vector<std::uint32_t> faceCount = readCounts(group.id(), "face_count");
  if (vertexCount.size() != faceCount.size())
    throw DatabaseError("convex_parts: vertex_count and face_count differ in length");
  const Points3 vertices =
      toMatrix<Points3>(h5::readDoubles(group.id(), "vertices"), "convex_parts/vertices");
  const Faces3 faces = toMatrix<Faces3>(h5::readUInt32s(group.id(), "faces"), "convex_parts/faces");
  std::uint64_t v = 0, f = 0;
  std::vector<ConvexPiece> parts(vertexCount.size());
  for (std::size_t i = 0; i < parts.size(); ++i) {
    if (v + vertexCount[i] > static_cast<std::uint64_t>(vertices.rows()) ||
        f + faceCount[i] > static_cast<std::uint64_t>(faces.rows()))
      throw DatabaseError("convex_parts: the counts exceed the vertices or faces");
    parts[i].vertices = vertices.middleRows(static_cast<Eigen::Index>(v), vertexCount[i]);
    parts[i].faces = faces.middleRows(static_cast<Eigen::Index>(f), faceCount[i]);
    v += vertexCount[i];
    f += faceCount[i];
  }
  if (v != static_cast<std::uint64_t>(vertices.rows()) ||
      f != static_cast<std::uint64_t>(faces.rows()))
    throw DatabaseError("convex_parts: the counts do not add up to the vertices and faces");
  return parts;
}

void writeContacts(hid_t file, const ObjectDatabase& db) {
  Handle group = h5::createGroup(file, "contacts");
  const auto n = db.positions.rows();
  h5::writeDataset(group.id(), "positions", db.positions.data(), shapeOf(n, 3));
  h5::writeDataset(group.id(), "normals", db.normals.data(), shapeOf(n, 3));
  h5::writeDataset(group.id(), "curvature", db.curvature.data(), {static_cast<hsize_t>(n)});
}

void readContacts(hid_t file, ObjectDatabase& db) {
  Handle group = h5::openGroup(file, "contacts");
  db.positions = toMatrix<Points3>(h5::readDoubles(group.id(), "positions"), "positions");
  db.normals = toMatrix<Points3>(h5::readDoubles(group.id(), "normals"), "normals");
  const h5::Array<double> curvature = h5::readDoubles(group.id(), "curvature");
  if (curvature.shape.size() != 1) throw DatabaseError("dataset 'curvature' must be 1-D");
  db.curvature = Eigen::Map<const Eigen::VectorXd>(
      curvature.data.data(), static_cast<Eigen::Index>(curvature.data.size()));
}

std::string levelName(std::size_t level) {
  return "level_" + std::to_string(level + 1);
}

void writeLevel(hid_t hierarchy, std::size_t level, const std::vector<HierarchyNode>& nodes) {
  Handle group = h5::createGroup(hierarchy, levelName(level));
  const std::size_t n = nodes.size();
  std::vector<std::uint32_t> columns[5];
  Points3 normals(static_cast<Eigen::Index>(n), 3);
  for (std::size_t i = 0; i < n; ++i) {
    const HierarchyNode& node = nodes[i];
    columns[0].push_back(node.contact_begin);
    columns[1].push_back(node.contact_count);
    columns[2].push_back(node.child_begin);
    columns[3].push_back(node.child_count);
    columns[4].push_back(node.representative);
    normals.row(static_cast<Eigen::Index>(i)) = node.mean_normal.transpose();
  }
  const char* names[5] = {"contact_begin", "contact_count", "child_begin", "child_count",
                          "representative"};
  for (int c = 0; c < 5; ++c) h5::writeDataset(group.id(), names[c], columns[c].data(), {n});
  h5::writeDataset(group.id(), "mean_normal", normals.data(), {n, 3});
}

std::vector<HierarchyNode> readLevel(hid_t hierarchy, std::size_t level) {
  Handle group = h5::openGroup(hierarchy, levelName(level));
  const char* names[5] = {"contact_begin", "contact_count", "child_begin", "child_count",
                          "representative"};
  std::vector<std::uint32_t> columns[5];
  for (int c = 0; c < 5; ++c) {
    h5::Array<std::uint32_t> column = h5::readUInt32s(group.id(), names[c]);
    if (column.shape.size() != 1) throw DatabaseError(std::string(names[c]) + " must be 1-D");
    columns[c] = std::move(column.data);
    if (columns[c].size() != columns[0].size())
      throw DatabaseError(levelName(level) + ": columns differ in length");
  }
  const Points3 normals =
      toMatrix<Points3>(h5::readDoubles(group.id(), "mean_normal"), "mean_normal");
  if (static_cast<std::size_t>(normals.rows()) != columns[0].size())
    throw DatabaseError(levelName(level) + ": mean_normal differs in length");
  std::vector<HierarchyNode> nodes(columns[0].size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    nodes[i] = {columns[0][i], columns[1][i],
                columns[2][i], columns[3][i],
                columns[4][i], normals.row(static_cast<Eigen::Index>(i)).transpose()};
  }
  return nodes;
}

void writeAll(hid_t file, const ObjectDatabase& db) {
  h5::writeFormat(file, kObjectFormatName, kObjectFormatVersion);
  h5::writeAttribute(file, "producer", db.producer);
  h5::writeAttribute(file, "name", db.name);
  h5::writeAttribute(file, "source_mesh", db.source_mesh);
  h5::writeAttribute(file, "source_sha256", db.source_sha256);
  h5::writeAttribute(file, "units", std::string("m"));
  h5::writeAttribute(file, "normals", std::string("outward"));
  writeParameters(file, db.parameters);
  {
    Handle group = h5::createGroup(file, "preprocess");
    std::vector<std::string> names;
    std::vector<std::uint64_t> removed;
    for (const FilterReport& r : db.filter_reports) {
      names.push_back(r.name);
      removed.push_back(r.removed);
    }
    h5::writeAttribute(group.id(), "num_samples", db.num_samples);
    h5::writeAttribute(group.id(), "filters", h5::joinNames(names));
    h5::writeAttribute(group.id(), "removed", removed);
  }
  if (db.partial_view) {
    Handle group = h5::createGroup(file, "partial_view");
    const PartialView& v = *db.partial_view;
    std::vector<double> viewpoints;
    for (Eigen::Index i = 0; i < v.viewpoints.rows(); ++i)
      for (int k = 0; k < 3; ++k) viewpoints.push_back(v.viewpoints(i, k));
    h5::writeAttribute(group.id(), "viewpoints", viewpoints);
    h5::writeAttribute(group.id(), "hidden_depths", v.hidden_depths);
    h5::writeAttribute(group.id(), "floors", v.floors);
    h5::writeAttribute(group.id(), "points", v.points);
    if (v.hidden_low.rows() > 0) {
      const auto n = v.hidden_low.rows();
      h5::writeDataset(group.id(), "hidden_low", v.hidden_low.data(), shapeOf(n, 3));
      h5::writeDataset(group.id(), "hidden_high", v.hidden_high.data(), shapeOf(n, 3));
      h5::writeAttribute(group.id(), "hidden_voxel", v.hidden_voxel);
    }
  }
  writeGeometry(file, db.geometry, db.density);
  writeDistanceGrid(file, db.geometry.distance_grid);
  writeConvexParts(file, db.geometry.convex_parts);
  writeContacts(file, db);
  Handle hierarchy = h5::createGroup(file, "hierarchy");
  h5::writeAttribute(hierarchy.id(), "branching", widened(db.parameters.branching));
  for (std::size_t l = 0; l < db.levels.size(); ++l) writeLevel(hierarchy.id(), l, db.levels[l]);
}

void readHeader(hid_t file, ObjectDatabase& db) {
  h5::checkFormat(file, kObjectFormatName, kObjectFormatVersion, "object database",
                  "hfts-preprocess MESH -o DIR");
  db.producer = h5::readStringAttribute(file, "producer");
  db.name = h5::readStringAttribute(file, "name");
  db.source_mesh = h5::readStringAttribute(file, "source_mesh");
  db.source_sha256 = h5::readStringAttribute(file, "source_sha256");
}

ObjectDatabase readAll(hid_t file) {
  ObjectDatabase db;
  readHeader(file, db);
  db.parameters = readParameters(file);
  {
    Handle group = h5::openGroup(file, "preprocess");
    db.num_samples = h5::readUInt64(group.id(), "num_samples");
    const std::vector<std::string> names =
        h5::splitNames(h5::readStringAttribute(group.id(), "filters"));
    const std::vector<std::uint64_t> removed = h5::readUInt64Attribute(group.id(), "removed");
    if (names.size() != removed.size())
      throw DatabaseError("preprocess: filters and removed differ in length");
    for (std::size_t i = 0; i < names.size(); ++i)
      db.filter_reports.push_back({names[i], removed[i]});
  }
  if (h5::exists(file, "partial_view")) {  // only in a database built from views
    Handle group = h5::openGroup(file, "partial_view");
    const std::vector<double> viewpoints = h5::readDoubleAttribute(group.id(), "viewpoints");
    PartialView& v = db.partial_view.emplace();
    v.hidden_depths = h5::readDoubleAttribute(group.id(), "hidden_depths");
    v.floors = h5::readDoubleAttribute(group.id(), "floors");
    v.points = h5::readUInt64Attribute(group.id(), "points");
    const std::size_t views = v.points.size();
    if (viewpoints.size() != 3 * views || v.hidden_depths.size() != views ||
        v.floors.size() != views)
      throw DatabaseError(
          "partial_view: viewpoints, hidden_depths, floors and points disagree "
          "in their number of views");
    if (h5::exists(group.id(), "hidden_low")) {
      v.hidden_low = toMatrix<Points3>(h5::readDoubles(group.id(), "hidden_low"), "hidden_low");
      v.hidden_high = toMatrix<Points3>(h5::readDoubles(group.id(), "hidden_high"), "hidden_high");
      v.hidden_voxel = h5::readDouble(group.id(), "hidden_voxel");
    }
    v.viewpoints.resize(static_cast<Eigen::Index>(views), 3);
    for (std::size_t i = 0; i < views; ++i)
      for (int k = 0; k < 3; ++k)
        v.viewpoints(static_cast<Eigen::Index>(i), k) =
            viewpoints[3 * i + static_cast<std::size_t>(k)];
  }
  db.geometry = readGeometry(file, db.density);
  db.geometry.distance_grid = readDistanceGrid(file);
  db.geometry.convex_parts = readConvexParts(file);
  readContacts(file, db);
  Handle hierarchy = h5::openGroup(file, "hierarchy");
  const std::size_t numLevels = db.parameters.branching.size();
  if (numLevels == 0 || numLevels > 16) throw DatabaseError("implausible number of levels");
  for (std::size_t l = 0; l < numLevels; ++l) db.levels.push_back(readLevel(hierarchy.id(), l));
  return db;
}

}  // namespace

void saveObjectDatabase(const ObjectDatabase& db, const std::filesystem::path& path) {
  const std::string what = "database '" + path.string() + "'";
  validateObjectDatabase(db, what);
  h5::writeAtomically(path, what, [&](hid_t file) { writeAll(file, db); });
}

ObjectDatabase loadObjectDatabase(const std::filesystem::path& path) {
  const std::string what = "database '" + path.string() + "'";
  ObjectDatabase db;
  h5::readFile(path, what, [&](hid_t file) { db = readAll(file); });
  validateObjectDatabase(db, what);
  DistanceGrid& grid = db.geometry.distance_grid;
  grid.boundary_min = boundaryMinimum(grid);  // derived, not stored
  return db;
}

}  // namespace hfts::db
