#include "handle_force.hpp"

#include <stdexcept>

#include "hapticd/chain_state.hpp"
#include "hapticd/plugin.hpp"

namespace hapticd::controllers {

ParameterSchema HandleForce::parameter_schema() {
  ParameterSchema s;
  s.real("stiffness_n_per_m",
         "admittance display: the position loop's stiffness; 0: the device's recommended largest stiffness")
      .unit("N/m")
      .minimum(0.0)
      .default_value(0.0);
  s.real("damping_n_s_per_m", "admittance display: the position loop's damping; 0: the device's recommended")
      .unit("N s/m")
      .minimum(0.0)
      .default_value(0.0);
  s.real("rotational_stiffness_nm_per_rad",
         "admittance display, devices with actuated torques: the orientation loop's stiffness; 0: recommended")
      .unit("N m/rad")
      .minimum(0.0)
      .default_value(0.0);
  s.real("rotational_damping_nm_s_per_rad", "the orientation loop's damping; 0: the device's recommended")
      .unit("N m s/rad")
      .minimum(0.0)
      .default_value(0.0);
  return s;
}

void HandleForce::configure(const Parameters& p, const PluginContext& context) {
  if (context.device == nullptr || context.device->interface != DeviceInterface::handle)
    throw std::invalid_argument("handle_force drives handle devices only");
  const HandleDescription& h = context.device->handle;
  world_to_base_ = to_isometry(context.base_pose).linear().transpose();
  axes_ = h.axes();
  torque_ = h.actuated_torque;
  // The device's recommendation is the ceiling: a larger gain than the vendor allows is refused.
  const auto gain = [&](const char* key, double recommended) {
    const double asked = p.real(key);
    if (asked > 0.0 && recommended > 0.0 && asked > recommended)
      throw ParameterError(key, "above the device's recommended " + std::to_string(recommended));
    return asked > 0.0 ? asked : recommended;
  };
  k_ = gain("stiffness_n_per_m", h.recommended_stiffness_n_per_m);
  d_ = gain("damping_n_s_per_m", h.recommended_damping_n_s_per_m);
  kr_ = gain("rotational_stiffness_nm_per_rad", h.recommended_rotational_stiffness_nm_per_rad);
  dr_ = gain("rotational_damping_nm_s_per_rad", h.recommended_rotational_damping_nm_s_per_rad);
}

Outcome HandleForce::activate(const ControllerInput& current, const JointCommand&) {
  if (!current.chain.has_handle) return Outcome::failure("handle_force: the device reports no handle");
  if (current.task.has_motion && !(k_ > 0.0))
    return Outcome::failure(
        "handle_force: admittance display needs a position loop, and neither the device nor the parameters "
        "give it a stiffness (stiffness_n_per_m)");
  return Outcome::success();
}

Outcome HandleForce::update(const CycleTime&, const ControllerInput& in, JointCommand& command) {
  const ChainState& c = in.chain;
  const TaskTarget& task = in.task;
  Eigen::Vector3d force = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
  if (task.has_motion) {
    force = k_ * (task.pose.position - c.handle_pose.position) + d_ * (task.twist.linear - c.handle_twist.linear);
    if (torque_) {
      const Eigen::AngleAxisd e(task.pose.orientation.normalized() *
                                c.handle_pose.orientation.normalized().conjugate());
      torque = kr_ * e.angle() * e.axis() + dr_ * (task.twist.angular - c.handle_twist.angular);
    }
  } else if (task.has_wrench) {
    force = task.wrench.force;
    torque = task.wrench.torque;
  }
  command.torque_nm.setZero(axes_);
  command.torque_nm.head<3>() = world_to_base_ * force;
  if (torque_) command.torque_nm.segment<3>(3) = world_to_base_ * torque;
  return Outcome::success();
}

}  // namespace hapticd::controllers

using namespace hapticd;

HAPTICD_PLUGIN_LIBRARY(describe_plugin<controllers::HandleForce>(
    "handle_force", "1.0.0", "handle devices: the rendered wrench as the handle's force, or a position loop"))
