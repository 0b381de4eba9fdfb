#pragma once
// The controller of handle devices ("handle_force", docs/devices.md): the handle takes a force, so the chain's
// task becomes the axes' efforts (hapticd/handle.hpp) in the device's base frame.
//   impedance display (the virtual model renders a wrench): force = the wrench's force, torque = its torque
//     where the device actuates torques;
//   admittance display (the virtual model gives a desired motion): a task-space position loop through the
//     force input, F = K (x_d - x) + D (v_d - v) (and the same for the orientation where torques are actuated),
//     its gains the device's recommended stiffness and damping unless the parameters give smaller ones - a
//     handle device has no joint torques to feed forward, so the loop is as stiff as the device allows.
// The gripper's force stays zero (no virtual model renders a gripper yet).
#include "hapticd/controller.hpp"

namespace hapticd::controllers {

class HandleForce final : public Controller {
 public:
  static constexpr DeviceInterfaces kDeviceInterfaces = kHandleOnly;
  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const PluginContext& context) override;
  Outcome activate(const ControllerInput& current, const JointCommand& last_command) override;
  Outcome update(const CycleTime& cycle, const ControllerInput& input, JointCommand& command) override;
  void deactivate() override {}

 private:
  Eigen::Matrix3d world_to_base_ = Eigen::Matrix3d::Identity();
  int axes_ = 3;
  bool torque_ = false;
  double k_ = 0.0, d_ = 0.0, kr_ = 0.0, dr_ = 0.0;
};

}  // namespace hapticd::controllers
