// The in-process Python module hfts._hfts (docs/python.md); the package
// hfts (python/hfts/__init__.py) re-exports it.

#include <nlohmann/json.hpp>

#include "bindings.h"
#include "core/invalid_argument.h"

namespace hfts::python {

py::object toPython(const nlohmann::json& value) {
  // Never released: a static py::object would be released after the
  // interpreter has finalised.
  static const py::handle loads = py::object(py::module_::import("json").attr("loads")).release();
  return loads(value.dump());
}

Eigen::Isometry3d isometryOf(const DoubleArray& array, const std::string& field) {
  checkShape(array, field, {4, 4});
  const Eigen::Matrix4d matrix =
      Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(array.data());
  const Eigen::Matrix3d r = matrix.topLeftCorner<3, 3>();
  if (!matrix.allFinite() || !(matrix.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).isZero(1e-9) ||
      !(r.transpose() * r).isIdentity(1e-6) || r.determinant() < 0.0)
    throw InvalidArgument(field,
                          "must be a finite 4 x 4 rigid transform (a rotation and a translation "
                          "over the row 0 0 0 1)");
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::Quaterniond(r).normalized().toRotationMatrix();
  pose.translation() = matrix.topRightCorner<3, 1>();
  return pose;
}

Eigen::Vector3d vector3Of(const DoubleArray& array, const std::string& field) {
  checkShape(array, field, {3});
  const Eigen::Vector3d v(array.data()[0], array.data()[1], array.data()[2]);
  if (!v.allFinite()) throw InvalidArgument(field, "must be finite");
  return v;
}

std::string describe(const char* name, const py::object& self) {
  std::string out = std::string("hfts.") + name + "(";
  bool first = true;
  for (const auto& item : self.attr("__class__").attr("__dict__").cast<py::dict>()) {
    const std::string key = py::str(item.first).cast<std::string>();
    if (key.rfind("_", 0) == 0 || !py::hasattr(item.second, "fset") ||
        item.second.attr("fset").is_none())
      continue;
    out += (first ? "" : ", ") + key + "=" + py::repr(self.attr(key.c_str())).cast<std::string>();
    first = false;
  }
  return out + ")";
}

std::uint64_t seedOf(const py::object& seed) {
  // Any integer, numpy's too (operator.index), but not a float.
  const py::object index = py::reinterpret_steal<py::object>(PyNumber_Index(seed.ptr()));
  if (!index) {
    PyErr_Clear();
    throw InvalidArgument("seed", "must be an integer in [0, 2^64)");
  }
  const unsigned long long value = PyLong_AsUnsignedLongLong(index.ptr());
  if (value == static_cast<unsigned long long>(-1) && PyErr_Occurred()) {
    PyErr_Clear();
    throw InvalidArgument("seed", "must be an integer in [0, 2^64)");
  }
  return value;
}

void checkShape(const DoubleArray& array, const std::string& field,
                std::initializer_list<py::ssize_t> shape) {
  bool ok = array.ndim() == static_cast<py::ssize_t>(shape.size());
  py::ssize_t d = 0;
  std::string wanted = "(";
  for (const py::ssize_t size : shape) {
    if (ok && size >= 0 && array.shape(d) != size) ok = false;
    wanted += (d ? ", " : "") + (size >= 0 ? std::to_string(size) : std::string("n"));
    ++d;
  }
  wanted += shape.size() == 1 ? ",)" : ")";
  if (!ok) {
    std::string got = "(";
    for (py::ssize_t i = 0; i < array.ndim(); ++i)
      got += (i ? ", " : "") + std::to_string(array.shape(i));
    got += array.ndim() == 1 ? ",)" : ")";
    throw InvalidArgument(field, "must be an array of shape " + wanted + ", got " + got);
  }
}

}  // namespace hfts::python

PYBIND11_MODULE(_hfts, m) {
  m.doc() =
      "Integrated fingertip-grasp and motion planning (docs/python.md): robots, scenes, object "
      "databases, grasp quality, planning, physics validation and trajectories, in process.";
  hfts::python::bindErrors(m);
  hfts::python::bindGrasp(m);
  hfts::python::bindRobot(m);
  hfts::python::bindSettings(m);
  hfts::python::bindPlanner(m);
}
