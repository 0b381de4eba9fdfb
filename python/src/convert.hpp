#pragma once
// NumPy views of the SDK's value types for the bindings.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <Eigen/Geometry>
#include <vector>

#include "hapticd/joint_vector.hpp"
#include "hapticd/parameter_info.hpp"

namespace hapticd::python {

namespace py = pybind11;

// [w, x, y, z], as on the wire.
inline py::array_t<double> quaternion_array(const Eigen::Quaterniond& q) {
  py::array_t<double> a(4);
  auto r = a.mutable_unchecked<1>();
  r(0) = q.w();
  r(1) = q.x();
  r(2) = q.y();
  r(3) = q.z();
  return a;
}
// From any sequence of four numbers [w, x, y, z]; normalised. Raises ValueError for another length or a zero
// quaternion.
Eigen::Quaterniond quaternion_from(const py::object& wxyz);
// A vector of n numbers from any sequence (ValueError for another length or non-finite values).
Eigen::VectorXd vector_from(const py::object& values, Eigen::Index n, const char* what);

// Request values: None (none), a number, or a sequence of numbers.
inline std::vector<double> values_of(const py::object& values) {
  if (values.is_none()) return {};
  if (py::isinstance<py::float_>(values) || py::isinstance<py::int_>(values)) return {py::cast<double>(values)};
  return py::cast<std::vector<double>>(values);
}

inline py::array_t<double> joint_array(const JointVector& v) {
  py::array_t<double> a(v.size());
  auto r = a.mutable_unchecked<1>();
  for (Eigen::Index i = 0; i < v.size(); ++i) r(i) = v[i];
  return a;
}

// A parameter's description as a dict: name, type, unit, description, tunable, minimum, maximum (None: no
// bound), minimum_exclusive, value (a list of numbers; text parameters: the text), value_text.
inline py::dict parameter_dict(const ParameterInfo& p) {
  py::dict d;
  d["name"] = p.name;
  d["type"] = std::string(to_string(p.type));
  d["unit"] = p.unit;
  d["description"] = p.description;
  d["tunable"] = p.tunable;
  d["minimum"] = p.minimum ? py::object(py::float_(*p.minimum)) : py::object(py::none());
  d["maximum"] = p.maximum ? py::object(py::float_(*p.maximum)) : py::object(py::none());
  d["minimum_exclusive"] = p.minimum_exclusive;
  d["value"] = p.type == ParameterType::string ? py::object(py::str(p.value_text)) : py::object(py::cast(p.value));
  d["value_text"] = p.value_text;
  return d;
}

}  // namespace hapticd::python
