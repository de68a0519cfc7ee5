#pragma once
// What the binding files of the Python module share (module.cpp calls each
// file's bind function once, in the order of its dependencies).

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <nlohmann/json_fwd.hpp>

#include <Eigen/Geometry>

#include <cstdint>
#include <string>

namespace hfts::python {

namespace py = pybind11;

/// The exception classes (hfts.Error and its subclasses) and the
/// translation of the libraries' exceptions to them.
void bindErrors(py::module_& m);
/// Robots, scenes, planning worlds, IK and collision checks.
void bindRobot(py::module_& m);
/// Grasp quality, object databases and hand maps.
void bindGrasp(py::module_& m);
/// The planner's typed settings, the physics check's options, motion goals.
void bindSettings(py::module_& m);
/// Plans, their validation, trajectories and ROS messages.
void bindPlanner(py::module_& m);

/// A planner parameter's value from Python as the text
/// planner::setSetting reads: a bool (numpy's too) as 0 or 1, an integer
/// or a float as Python writes it, a string as it is. Throws
/// InvalidArgument ("parameters.<name>") for anything else.
std::string parameterText(const std::string& name, const py::handle& value);

/// JSON as Python objects (dict, list, float, int, str, bool, None).
py::object toPython(const nlohmann::json& value);

/// A configuration from Python (any sequence of numbers or a 1-D array).
using Configuration = Eigen::VectorXd;

/// A C-contiguous float64 array of Python's, converted (copied) only when
/// it is not one already. (Fixed-size Eigen arguments are avoided: their
/// pybind11 caster trips GCC's maybe-uninitialized warning.)
using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// A 4 x 4 homogeneous matrix as a rigid transform. Throws InvalidArgument
/// (`field`) for another shape, a matrix that is not finite or not a
/// rotation and a translation over the row 0 0 0 1.
Eigen::Isometry3d isometryOf(const DoubleArray& matrix, const std::string& field);

/// A 3-vector. Throws InvalidArgument (`field`) for another shape or a
/// value that is not finite.
Eigen::Vector3d vector3Of(const DoubleArray& vector, const std::string& field);

/// "hfts.<name>(field=value, ...)" of an object whose fields are its
/// class's properties that can be set, in the order they were defined.
std::string describe(const char* name, const py::object& self);

/// Gives a class of such fields (settings, options) that __repr__.
template <typename Class>
void addRepr(Class& cls, const char* name) {
  cls.def("__repr__", [name](const py::object& self) { return describe(name, self); });
}

/// A seed from Python. Throws InvalidArgument ("seed") for an integer
/// outside [0, 2^64).
std::uint64_t seedOf(const py::object& seed);

/// Throws InvalidArgument (`field`) unless `array` has `dims` dimensions
/// and, where `shape` is not -1, those sizes.
void checkShape(const DoubleArray& array, const std::string& field,
                std::initializer_list<py::ssize_t> shape);

}  // namespace hfts::python
