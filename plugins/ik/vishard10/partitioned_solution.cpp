#include "partitioned_solution.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "hapticd/model/kinematics.hpp"
#include "hapticd/model/robot_model.hpp"

namespace hapticd::ik::vishard10 {
namespace {

constexpr double kPi = std::numbers::pi;

Eigen::Matrix3d rz(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix(); }
Eigen::Matrix3d ry(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()).toRotationMatrix(); }
Eigen::Matrix3d rx(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()).toRotationMatrix(); }

const Eigen::Matrix3d& fixed_a() {
  static const Eigen::Matrix3d m = ry(kPi / 2) * rz(kPi);
  return m;
}
const Eigen::Matrix3d& fixed_b() {
  static const Eigen::Matrix3d m = ry(kPi / 2);
  return m;
}
const Eigen::Matrix3d& fixed_c() {
  static const Eigen::Matrix3d m = ry(kPi / 2) * rx(kPi);
  return m;
}

}  // namespace

Geometry Geometry::from(const model::RobotModel& model, int handle_frame) {
  if (model.dof() != 10)
    throw std::invalid_argument("the ViSHaRD10 solution needs a 10-joint model, got " + std::to_string(model.dof()));
  model::ModelData d(model);
  const JointVector zero = JointVector::Zero(10);
  model::forward_kinematics(model, d, zero);
  Geometry g;
  g.base = d.position[0].head<2>();
  for (int i = 0; i < 4; ++i)
    g.scara_link[static_cast<std::size_t>(i)] = (d.position[i + 1] - d.position[i]).head<2>().norm();
  g.z6 = d.position[5].z();
  const Eigen::Isometry3d handle = model::frame_pose(model, d, handle_frame);
  g.l67 = handle.translation().z() - g.z6;
  // The structure the solution relies on, checked on the model.
  const auto fail = [](const std::string& what) { throw std::invalid_argument("not a ViSHaRD10 structure: " + what); };
  for (int i = 0; i < 5; ++i)
    if ((d.rotation[i] - Eigen::Matrix3d::Identity()).norm() > 1e-9) fail("joints 1-5 must turn about the vertical");
  if (std::abs(g.scara_link[0] - g.scara_link[1]) > 1e-6 || std::abs(g.scara_link[2] - g.scara_link[3]) > 1e-6)
    fail("SCARA links 1, 2 and 3, 4 must be equal");
  if ((handle.translation().head<2>() - d.position[4].head<2>()).norm() > 1e-6)
    fail("the handle point must lie on joint 5's axis");
  if ((d.rotation[5] - fixed_a()).norm() > 1e-9 ||
      (d.rotation[7].transpose() * d.rotation[8] - fixed_b()).norm() > 1e-9 ||
      (d.rotation[8].transpose() * d.rotation[9] - fixed_c()).norm() > 1e-9 ||
      (d.rotation[9].transpose() * handle.linear() - Eigen::Matrix3d::Identity()).norm() > 1e-9)
    fail("the wrist's fixed rotations differ");
  if (!(g.l67 > 0.0)) fail("joints 6 and 7 must lift the handle");
  return g;
}

bool prismatic_pair(const Geometry& g, double z, double& q6, double& q7, double margin) noexcept {
  const double c = (z - g.z6) / g.l67;
  const double clamped = std::clamp(c, -1.0 + margin, 1.0 - margin);
  q6 = -std::acos(clamped);
  q7 = -2.0 * q6;
  return clamped == c;
}

bool scara_inverse_function(const Geometry& g, const Eigen::Vector2d& target, double yaw, int branch12, int branch34,
                            double q[4], double limit) noexcept {
  const Eigen::Vector2d r = target - g.base;
  const Eigen::Vector2d a(std::cos(yaw), std::sin(yaw)), b(-std::sin(yaw), std::cos(yaw));
  const double u_free = r.dot(a) / (2.0 * g.scara_link[0]);
  const double v_free = r.dot(b) / (2.0 * g.scara_link[2]);
  const double u = std::clamp(u_free, -limit, limit), v = std::clamp(v_free, -limit, limit);
  const double phi = (branch12 >= 0 ? 1.0 : -1.0) * std::acos(u);
  const double psi = (branch34 >= 0 ? 1.0 : -1.0) * std::acos(v);
  // Absolute link yaws: yaw + phi, yaw - phi, yaw + pi/2 + psi, yaw + pi/2 - psi.
  q[0] = yaw + phi;
  q[1] = -2.0 * phi;
  q[2] = kPi / 2 + psi + phi;
  q[3] = -2.0 * psi;
  return u == u_free && v == v_free;
}

Eigen::Matrix3d wrist_rotation(double q5_abs, double q8_abs, double q9, double q10) noexcept {
  return rz(q5_abs) * fixed_a() * rz(q8_abs) * fixed_b() * rz(q9) * fixed_c() * rz(q10);
}

Eigen::Matrix3d wrist_axes(double q5_abs, double q8_abs, double q9, double q10,
                           Eigen::Matrix<double, 3, 4>& axes) noexcept {
  // Each joint turns about the z axis of the frame before it: the z columns of the partial products.
  const Eigen::Matrix3d r5 = rz(q5_abs);
  const Eigen::Matrix3d r8 = r5 * fixed_a() * rz(q8_abs);
  const Eigen::Matrix3d r9 = r8 * fixed_b() * rz(q9);
  const Eigen::Matrix3d r10 = r9 * fixed_c() * rz(q10);
  axes.col(0) = r5.col(2);
  axes.col(1) = r8.col(2);
  axes.col(2) = r9.col(2);
  axes.col(3) = r10.col(2);
  return r10;
}

double wrist_inverse_function(const Eigen::Matrix3d& rotation, double q5_abs, double& q8_abs, double& q9,
                              double& q10) noexcept {
  const Eigen::Matrix3d m = (rz(q5_abs) * fixed_a()).transpose() * rotation;
  const Eigen::Vector3d v = m.col(2);  // joint 10's axis: (sin q8' sin q9, -cos q8' sin q9, cos q9)
  q9 = std::atan2(std::hypot(v.x(), v.y()), v.z());
  q8_abs = std::atan2(v.x(), -v.y());
  const Eigen::Matrix3d rest = (rz(q8_abs) * fixed_b() * rz(q9) * fixed_c()).transpose() * m;  // Rz(q10)
  q10 = std::atan2(rest(1, 0), rest(0, 0));
  return q9;
}

double unwrap_near(double value, double previous) noexcept {
  return value + 2.0 * kPi * std::round((previous - value) / (2.0 * kPi));
}

}  // namespace hapticd::ik::vishard10
