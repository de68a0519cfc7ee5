// Grasp quality (one grasp, or many in one call) and object databases.

#include "batch.h"
#include "bindings.h"
#include "core/invalid_argument.h"
#include "hfts_db/object_database.h"
#include "preprocess/database_builder.h"
#include "robot/scene.h"

namespace hfts::python {
namespace {

/// The query's fields but the contacts, checked as graspQuality checks them.
grasp::GraspQualityRequest commonRequest(const Eigen::Vector3d& center, double torqueScale,
                                         double friction, int coneEdges, double torsionalFriction,
                                         const std::string& normals) {
  if (normals != "inward" && normals != "outward")
    throw InvalidArgument("normal_direction",
                          "must be \"inward\" or \"outward\", got \"" + normals + "\"");
  grasp::GraspQualityRequest request;
  request.center = center;
  request.torque_scale = torqueScale;
  request.friction = friction;
  request.cone_edges = coneEdges;
  request.torsional_friction = torsionalFriction;
  request.direction =
      normals == "inward" ? grasp::NormalDirection::kInward : grasp::NormalDirection::kOutward;
  return request;
}

/// graspQuality's std::invalid_argument ("<field>: <problem>") as the
/// project's InvalidArgument, its field prefixed with `prefix`.
[[noreturn]] void rethrowQualityError(const std::invalid_argument& e, const std::string& prefix) {
  const std::string what = e.what();
  const std::size_t colon = what.find(": ");
  if (colon == std::string::npos) throw InvalidArgument(prefix, what);
  throw InvalidArgument(
      prefix.empty() ? what.substr(0, colon) : prefix + "." + what.substr(0, colon),
      what.substr(colon + 2));
}

double quality(const DoubleArray& positions, const DoubleArray& normals,
               const grasp::GraspQualityRequest& common) {
  checkShape(positions, "positions", {-1, 3});
  checkShape(normals, "normals", {positions.shape(0), 3});
  double epsilon = 0.0;
  try {
    graspQualities(positions.data(), normals.data(), 1, static_cast<int>(positions.shape(0)),
                   common, &epsilon);
  } catch (const InvalidArgument& e) {
    // graspQualities names the grasp ("grasps[0].normals[1]"); one grasp
    // has no index.
    const std::string prefix = "grasps[0].";
    const std::string& field = e.field();
    throw InvalidArgument(field.rfind(prefix, 0) == 0 ? field.substr(prefix.size()) : field,
                          e.problem());
  }
  return epsilon;
}

py::array_t<double> qualityBatch(const DoubleArray& positions, const DoubleArray& normals,
                                 const grasp::GraspQualityRequest& common) {
  checkShape(positions, "positions", {-1, -1, 3});
  checkShape(normals, "normals", {positions.shape(0), positions.shape(1), 3});
  const auto grasps = static_cast<std::size_t>(positions.shape(0));
  const int contacts = static_cast<int>(positions.shape(1));
  py::array_t<double> out(static_cast<py::ssize_t>(grasps));
  const double* p = positions.data();
  const double* n = normals.data();
  double* epsilons = out.mutable_data();
  py::gil_scoped_release release;
  graspQualities(p, n, grasps, contacts, common, epsilons);
  return out;
}

/// The epsilon of contacts of a database (indices into its contacts).
double databaseQuality(const db::ObjectDatabase& object, const std::vector<std::int64_t>& contacts,
                       double friction, int coneEdges, double torsionalFriction) {
  if (contacts.empty()) throw InvalidArgument("contacts", "must name at least one contact");
  grasp::GraspQualityRequest request =
      commonRequest(object.geometry.center_of_mass, object.geometry.rho, friction, coneEdges,
                    torsionalFriction, "outward");
  request.positions.resize(3, static_cast<Eigen::Index>(contacts.size()));
  request.normals.resize(3, static_cast<Eigen::Index>(contacts.size()));
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const std::int64_t c = contacts[i];
    if (c < 0 || c >= static_cast<std::int64_t>(object.numContacts()))
      throw InvalidArgument(
          "contacts[" + std::to_string(i) + "]",
          "must be a contact index below " + std::to_string(object.numContacts()));
    request.positions.col(static_cast<Eigen::Index>(i)) = object.positions.row(c).transpose();
    request.normals.col(static_cast<Eigen::Index>(i)) = object.normals.row(c).transpose();
  }
  try {
    return grasp::graspQuality(request).epsilon;
  } catch (const std::invalid_argument& e) {
    rethrowQualityError(e, "");
  }
}

db::ObjectDatabase buildFromArrays(const DoubleArray& vertices, const py::array& given_triangles,
                                   const std::string& name,
                                   const std::optional<db::BuildParameters>& given,
                                   double density) {
  const db::BuildParameters parameters = given.value_or(db::BuildParameters{});
  checkShape(vertices, "vertices", {-1, 3});
  // Integers only: a float index would be truncated silently.
  const char kind = given_triangles.dtype().kind();
  if ((kind != 'i' && kind != 'u') || given_triangles.ndim() != 2 || given_triangles.shape(1) != 3)
    throw InvalidArgument("triangles",
                          "must be an integer array of shape (n, 3) of vertex indices");
  const auto triangles =
      py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(given_triangles);
  if (!robot::isSafeName(name))
    throw InvalidArgument("name", "must be a file stem (letters, digits, '_', '-', '.')");
  if (!(density > 0.0) || !std::isfinite(density))
    throw InvalidArgument("density", "must be a finite number > 0 (kg/m^3)");
  TriangleMesh mesh;
  mesh.vertices = Eigen::Map<const Vertices>(vertices.data(), vertices.shape(0), 3);
  mesh.triangles.resize(triangles.shape(0), 3);
  const std::int64_t* t = triangles.data();
  for (py::ssize_t i = 0; i < triangles.size(); ++i) {
    if (t[i] < 0 || t[i] >= vertices.shape(0))
      throw InvalidArgument("triangles[" + std::to_string(i / 3) + "]",
                            "vertex index " + std::to_string(t[i]) + " is not below " +
                                std::to_string(vertices.shape(0)));
    mesh.triangles.data()[i] = static_cast<std::uint32_t>(t[i]);
  }
  py::gil_scoped_release release;
  preprocess::checkBuildParameters(parameters);
  sanitizeMesh(mesh, name);
  const bool closed = analyzeTopology(mesh).closed();
  preprocess::BuildResult built = preprocess::buildObjectDatabase(mesh, closed, parameters, name);
  built.database.name = name;
  built.database.source_mesh = "(arrays from Python)";
  built.database.density = density;
  return std::move(built.database);
}

/// Defines `name`: `compute` of the contacts and the query's other fields
/// (the arguments grasp_quality and grasp_quality_batch share).
template <typename Result>
void defineQuality(py::module_& m, const char* name,
                   Result (*compute)(const DoubleArray&, const DoubleArray&,
                                     const grasp::GraspQualityRequest&),
                   const char* doc) {
  m.def(
      name,
      [compute](const DoubleArray& positions, const DoubleArray& normals,
                const std::optional<DoubleArray>& center, double torque_scale, double friction,
                int cone_edges, double torsional_friction, const std::string& normal_direction) {
        return compute(
            positions, normals,
            commonRequest(center ? vector3Of(*center, "center") : Eigen::Vector3d::Zero(),
                          torque_scale, friction, cone_edges, torsional_friction,
                          normal_direction));
      },
      py::arg("positions"), py::arg("normals"), py::arg("center") = py::none(),
      py::arg("torque_scale") = 1.0, py::arg("friction") = 0.5, py::arg("cone_edges") = 8,
      py::arg("torsional_friction") = 0.0, py::arg("normal_direction") = "inward", doc);
}

}  // namespace

void bindGrasp(py::module_& m) {
  defineQuality(m, "grasp_quality", &quality,
                "Ferrari-Canny epsilon (docs/grasp_quality.md) of contacts at `positions` (k, 3) "
                "with unit `normals` (k, 3), torques about `center` (default the origin) scaled "
                "by 1 / torque_scale.");
  defineQuality(m, "grasp_quality_batch", &qualityBatch,
                "grasp_quality of N grasps of k contacts each in one call: positions and normals "
                "(N, k, 3), an array of N epsilons. The GIL is released while it runs.");

  py::class_<db::BuildParameters> buildParameters(
      m, "BuildParameters",
      "How an object database is built (hfts-preprocess's options, docs/preprocess.md).");
  buildParameters.def(py::init<>())
      .def_readwrite("scale", &db::BuildParameters::scale)
      .def_readwrite("sample_density", &db::BuildParameters::sample_density)
      .def_readwrite("max_samples", &db::BuildParameters::max_samples)
      .def_readwrite("viewpoints", &db::BuildParameters::viewpoints)
      .def_readwrite("pad_radius", &db::BuildParameters::pad_radius)
      .def_readwrite("filters", &db::BuildParameters::filters)
      .def_readwrite("max_curvature", &db::BuildParameters::max_curvature)
      .def_readwrite("branching", &db::BuildParameters::branching)
      .def_readwrite("seed", &db::BuildParameters::seed);
  addRepr(buildParameters, "BuildParameters");

  py::class_<db::ObjectDatabase>(m, "ObjectDatabase",
                                 "An object's HFTS database (docs/database.md): contacts "
                                 "in hierarchy order with outward normals, geometry, hierarchy.")
      .def_static(
          "load", [](const std::filesystem::path& path) { return db::loadObjectDatabase(path); },
          py::arg("path"), "Reads a database file (HDF5, hfts-preprocess's output).")
      .def_static(
          "build",
          [](const std::filesystem::path& mesh,
             const std::optional<db::BuildParameters>& parameters, double density) {
            py::gil_scoped_release release;
            return std::move(preprocess::buildObjectDatabaseFromFile(
                                 mesh, parameters.value_or(db::BuildParameters{}), density)
                                 .database);
          },
          py::arg("mesh"), py::arg("parameters") = py::none(),
          py::arg("density") = db::kDefaultDensity,
          "Builds the database of a mesh file (as hfts-preprocess does; a sidecar beside the "
          "mesh sets its density).")
      .def_static("from_arrays", &buildFromArrays, py::arg("vertices"), py::arg("triangles"),
                  py::arg("name"), py::arg("parameters") = py::none(),
                  py::arg("density") = db::kDefaultDensity,
                  "Builds the database of a mesh given as arrays: vertices (V, 3) in metres "
                  "(before parameters.scale), triangles (T, 3) of vertex indices.")
      .def(
          "save",
          [](const db::ObjectDatabase& d, const std::filesystem::path& path) {
            db::saveObjectDatabase(d, path);
          },
          py::arg("path"), "Writes the database (HDF5, atomically).")
      .def_readonly("name", &db::ObjectDatabase::name)
      .def_property_readonly("num_contacts", &db::ObjectDatabase::numContacts)
      .def_property_readonly("num_levels",
                             [](const db::ObjectDatabase& d) { return d.levels.size(); })
      .def_readonly("positions", &db::ObjectDatabase::positions,
                    "Contact positions (n, 3), hierarchy order (a read-only view).")
      .def_readonly("normals", &db::ObjectDatabase::normals,
                    "Unit normals (n, 3) pointing out of the object (a read-only view).")
      .def_property_readonly("center_of_mass",
                             [](const db::ObjectDatabase& d) { return d.geometry.center_of_mass; })
      .def_property_readonly(
          "rho", [](const db::ObjectDatabase& d) { return d.geometry.rho; },
          "The largest distance from the centre of mass to the surface (m): the quality's "
          "torque scale.")
      .def_property_readonly(
          "mass", [](const db::ObjectDatabase& d) { return d.density * d.geometry.volume; })
      .def_property_readonly(
          "mesh_vertices",
          [](const db::ObjectDatabase& d) -> const db::Points3& {
            return d.geometry.mesh_vertices;
          },
          py::return_value_policy::reference_internal)
      .def_property_readonly(
          "mesh_triangles",
          [](const db::ObjectDatabase& d) -> const db::Faces3& {
            return d.geometry.mesh_triangles;
          },
          py::return_value_policy::reference_internal)
      .def("grasp_quality", &databaseQuality, py::arg("contacts"), py::arg("friction") = 0.5,
           py::arg("cone_edges") = 8, py::arg("torsional_friction") = 0.0,
           "Epsilon of a grasp on contacts of this database (their indices), about its centre "
           "of mass scaled by rho.")
      .def("__repr__", [](const db::ObjectDatabase& d) {
        return "<hfts.ObjectDatabase '" + d.name + "' with " + std::to_string(d.numContacts()) +
               " contacts>";
      });
}

}  // namespace hfts::python
