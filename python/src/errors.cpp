// The libraries' exceptions as Python exceptions: every error about an
// input is an hfts.Error and a ValueError, carrying the field it names.

#include "bindings.h"
#include "core/invalid_argument.h"
#include "hfts_db/object_database.h"
#include "hfts_db/triangle_mesh.h"
#include "robot/robot_model.h"
#include "robot/scene.h"

namespace hfts::python {
namespace {

/// A new exception class hfts.<name> with `bases` and `doc` (the module
/// holds it; the handle returned borrows it).
py::handle exceptionClass(py::module_& m, const char* name, py::tuple bases, const char* doc) {
  const std::string qualified = std::string("hfts.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr);
  if (type == nullptr) throw py::error_already_set();
  m.attr(name) = py::reinterpret_steal<py::object>(type);
  return type;
}

/// Raises `cls(message)` with the attributes `field` and `problem`.
void raise(py::handle cls, const char* message, const std::string& field,
           const std::string& problem) {
  py::object error = cls(message);
  error.attr("field") = field;
  error.attr("problem") = problem;
  PyErr_SetObject(cls.ptr(), error.ptr());
}

}  // namespace

void bindErrors(py::module_& m) {
  const py::object exception = py::reinterpret_borrow<py::object>(PyExc_Exception);
  const py::object valueError = py::reinterpret_borrow<py::object>(PyExc_ValueError);
  // Handles, not objects: the module keeps the classes alive, and a static
  // py::object would be released after the interpreter has finalised.
  static py::handle error, invalid, scene, model, mesh, database;
  error = exceptionClass(m, "Error", py::make_tuple(exception),
                         "Every error of hfts; `field` names the input that is wrong (may be "
                         "empty) and `problem` says what is wrong with it.");
  invalid = exceptionClass(m, "InvalidArgument", py::make_tuple(error, valueError),
                           "A bad argument: `field` names it (\"start\", "
                           "\"parameters.p_max\", \"poses[3]\"), `problem` says what is wrong.");
  scene = exceptionClass(m, "SceneError", py::make_tuple(error, valueError),
                         "A scene that cannot be read; `field` is the bad member's path.");
  model = exceptionClass(m, "ModelError", py::make_tuple(error, valueError),
                         "A robot description (URDF, config) that cannot be used.");
  mesh = exceptionClass(m, "MeshError", py::make_tuple(error, valueError),
                        "A mesh that cannot be read or holds nothing graspable.");
  database = exceptionClass(m, "DatabaseError", py::make_tuple(error, valueError),
                            "An object database or hand map file that cannot be read or "
                            "written.");
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InvalidArgument& e) {
      raise(invalid, e.what(), e.field(), e.problem());
    } catch (const robot::SceneError& e) {
      raise(scene, e.what(), e.field(), e.problem());
    } catch (const robot::ModelError& e) {
      raise(model, e.what(), "", e.what());
    } catch (const MeshError& e) {
      raise(mesh, e.what(), "", e.what());
    } catch (const db::DatabaseError& e) {
      raise(database, e.what(), "", e.what());
    }
  });
}

}  // namespace hfts::python
