// Pose, Twist and Wrench: the SDK's value types with NumPy fields (world frame, SI units).
#include <pybind11/stl.h>

#include <cmath>

#include "bindings.hpp"
#include "convert.hpp"
#include "hapticd/spatial.hpp"

namespace hapticd::python {

Eigen::VectorXd vector_from(const py::object& values, Eigen::Index n, const char* what) {
  const auto v = py::cast<Eigen::VectorXd>(py::array_t<double, py::array::forcecast>(values).attr("ravel")());
  if (v.size() != n)
    throw py::value_error(std::string(what) + ": " + std::to_string(n) + " numbers expected, got " +
                          std::to_string(v.size()));
  if (!v.allFinite()) throw py::value_error(std::string(what) + ": not finite");
  return v;
}

Eigen::Quaterniond quaternion_from(const py::object& wxyz) {
  const Eigen::VectorXd v = vector_from(wxyz, 4, "orientation [w, x, y, z]");
  if (v.norm() < 1e-9) throw py::value_error("orientation [w, x, y, z]: a zero quaternion");
  return Eigen::Quaterniond(v[0], v[1], v[2], v[3]).normalized();
}

namespace {
Eigen::Vector3d vector3(const py::object& values, const char* what) { return vector_from(values, 3, what); }

std::string format3(const Eigen::Vector3d& v) {
  return "[" + std::to_string(v.x()) + ", " + std::to_string(v.y()) + ", " + std::to_string(v.z()) + "]";
}
}  // namespace

void bind_spatial(py::module_& m) {
  py::class_<Pose>(m, "Pose", "A pose: position [m] and orientation as a unit quaternion [w, x, y, z].")
      .def(py::init([](const py::object& position, const py::object& orientation) {
             return Pose{vector3(position, "position"), quaternion_from(orientation)};
           }),
           py::arg("position") = py::make_tuple(0.0, 0.0, 0.0),
           py::arg("orientation") = py::make_tuple(1.0, 0.0, 0.0, 0.0))
      .def_property(
          "position", [](const Pose& p) { return Eigen::Vector3d(p.position); },
          [](Pose& p, const py::object& v) { p.position = vector3(v, "position"); }, "[x, y, z] in m (a copy)")
      .def_property(
          "orientation", [](const Pose& p) { return quaternion_array(p.orientation); },
          [](Pose& p, const py::object& q) { p.orientation = quaternion_from(q); }, "[w, x, y, z] (a copy)")
      .def("rotation_matrix",
           [](const Pose& p) { return Eigen::Matrix3d(p.orientation.normalized().toRotationMatrix()); })
      .def("__repr__", [](const Pose& p) {
        return "Pose(position=" + format3(p.position) + ", orientation=[" + std::to_string(p.orientation.w()) + ", " +
               std::to_string(p.orientation.x()) + ", " + std::to_string(p.orientation.y()) + ", " +
               std::to_string(p.orientation.z()) + "])";
      });

  py::class_<Twist>(m, "Twist", "Linear [m/s] and angular [rad/s] velocity (also accelerations).")
      .def(py::init([](const py::object& linear, const py::object& angular) {
             return Twist{vector3(linear, "linear"), vector3(angular, "angular")};
           }),
           py::arg("linear") = py::make_tuple(0.0, 0.0, 0.0), py::arg("angular") = py::make_tuple(0.0, 0.0, 0.0))
      .def_property(
          "linear", [](const Twist& t) { return Eigen::Vector3d(t.linear); },
          [](Twist& t, const py::object& v) { t.linear = vector3(v, "linear"); })
      .def_property(
          "angular", [](const Twist& t) { return Eigen::Vector3d(t.angular); },
          [](Twist& t, const py::object& v) { t.angular = vector3(v, "angular"); })
      .def("__repr__", [](const Twist& t) {
        return "Twist(linear=" + format3(t.linear) + ", angular=" + format3(t.angular) + ")";
      });

  py::class_<Wrench>(m, "Wrench", "Force [N] and torque [N m].")
      .def(py::init([](const py::object& force, const py::object& torque) {
             return Wrench{vector3(force, "force"), vector3(torque, "torque")};
           }),
           py::arg("force") = py::make_tuple(0.0, 0.0, 0.0), py::arg("torque") = py::make_tuple(0.0, 0.0, 0.0))
      .def_property(
          "force", [](const Wrench& w) { return Eigen::Vector3d(w.force); },
          [](Wrench& w, const py::object& v) { w.force = vector3(v, "force"); })
      .def_property(
          "torque", [](const Wrench& w) { return Eigen::Vector3d(w.torque); },
          [](Wrench& w, const py::object& v) { w.torque = vector3(v, "torque"); })
      .def("__repr__",
           [](const Wrench& w) { return "Wrench(force=" + format3(w.force) + ", torque=" + format3(w.torque) + ")"; });
}

}  // namespace hapticd::python
