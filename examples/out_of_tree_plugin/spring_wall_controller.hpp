// Example plugin: joint PD tracking of the chain's joint target, plus a stiff one-sided virtual wall at
// wall_position on the first joint. Shows the whole plugin contract: a parameter schema, configure() that
// validates and reports a bad key by name, a real-time update() without allocation. (The library's entry, for
// all the examples: plugins.cpp.)
#pragma once
#include <hapticd/plugin.hpp>

namespace example {

class SpringWallController final : public hapticd::Controller {
 public:
  static hapticd::ParameterSchema parameter_schema() {
    hapticd::ParameterSchema s;
    s.real("kp", "joint position gain").unit("N/m").minimum(0.0).default_value(100.0);
    s.real("kd", "joint velocity gain").unit("N s/m").minimum(0.0).default_value(10.0);
    s.real("wall_position", "wall on joint 1; the wall pushes back above it").unit("m");
    s.real("wall_stiffness", "wall spring").unit("N/m").greater_than(0.0).default_value(5000.0);
    s.real("wall_damping", "wall damper (only while penetrating)").unit("N s/m").minimum(0.0).default_value(20.0);
    return s;
  }

  void configure(const hapticd::Parameters& p, const hapticd::PluginContext& context) override {
    kp_ = p.real("kp");
    kd_ = p.real("kd");
    wall_ = p.real("wall_position");
    k_wall_ = p.real("wall_stiffness");
    d_wall_ = p.real("wall_damping");
    dof_ = context.device->dof();
    const auto& joint = context.device->joints.front();
    if (wall_ < joint.position_min || wall_ > joint.position_max)
      throw hapticd::ParameterError("wall_position", "the wall lies outside joint 1's range");
  }

  hapticd::Outcome activate(const hapticd::ControllerInput&, const hapticd::JointCommand&) override {
    return hapticd::Outcome::success();
  }

  hapticd::Outcome update(const hapticd::CycleTime&, const hapticd::ControllerInput& in,
                          hapticd::JointCommand& out) override {
    const auto& q = in.device.joints.position;
    const auto& qd = in.device.joints.velocity;
    for (int i = 0; i < dof_; ++i)
      out.torque_nm[i] =
          in.joints.valid ? kp_ * (in.joints.position[i] - q[i]) + kd_ * (in.joints.velocity[i] - qd[i]) : 0.0;
    const double penetration = q[0] - wall_;
    if (penetration > 0.0) out.torque_nm[0] -= k_wall_ * penetration + d_wall_ * qd[0];
    return hapticd::Outcome::success();
  }

  void deactivate() override {}

 private:
  double kp_ = 0, kd_ = 0, wall_ = 0, k_wall_ = 0, d_wall_ = 0;
  int dof_ = 0;
};

}  // namespace example
