#pragma once
#include <cstdint>

#include "hapticd/controller.hpp"
#include "hapticd/signal/differentiator.hpp"

namespace hapticd::test_plugins {

// Joint PD control towards the IK's joint target (or a fixed setpoint when the chain has no IK):
// tau = kp (q_d - q) + kd (qd_d - qd), with qd differentiated from the positions (first-order filter) for
// devices that do not report velocities. fault_at_cycle makes it emit a non-finite torque, for fault tests.
class PdController final : public Controller {
 public:
  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const PluginContext& context) override;
  ReturnCode activate(const ControllerInput& current, const JointCommand& last_command) noexcept override;
  ReturnCode update(const CycleTime& cycle, const ControllerInput& input, JointCommand& command) noexcept override;
  void deactivate() override {}

 private:
  double kp_ = 0.0;
  double kd_ = 0.0;
  double setpoint_ = 0.0;
  std::int64_t fault_at_cycle_ = -1;
  int dof_ = 0;
  bool hold_at_activation_ = false;
  bool differentiate_ = false;
  signal::Differentiator<JointVector> differentiator_;
  JointVector hold_, velocity_;
};

}  // namespace hapticd::test_plugins
