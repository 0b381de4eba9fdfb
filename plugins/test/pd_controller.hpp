#pragma once
#include <cstdint>

#include "hapticd/controller.hpp"
#include "hapticd/signal/differentiator.hpp"

namespace hapticd::test_plugins {

// Joint PD control towards the IK's joint target (or a fixed setpoint when the chain has no IK):
// tau = kp (q_d - q) + kd (qd_d - qd), with qd differentiated from the positions (first-order filter) for
// devices that do not report velocities. Fault injection: fault_at_cycle (a non-finite torque), throw_at_cycle
// (an exception from update()), throw_in_configure, the request break_invariant.
class PdController final : public Controller {
 public:
  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const PluginContext& context) override;
  Outcome activate(const ControllerInput& current, const JointCommand& last_command) override;
  // Not noexcept: throw_at_cycle tests that the server survives a plugin breaking the contract.
  Outcome update(const CycleTime& cycle, const ControllerInput& input, JointCommand& command) override;
  void deactivate() override;
  // Fault injection: "break_invariant" fails an invariant check (HAPTICD_DEMAND) on the requesting thread - the
  // server's handling of a broken invariant off the loop (docs/safety.md) is tested with it.
  RuntimeReply handle_request(std::string_view name, const std::vector<double>& values) override;

 private:
  double kp_ = 0.0;
  double kd_ = 0.0;
  double setpoint_ = 0.0;
  std::int64_t fault_at_cycle_ = -1;
  std::int64_t throw_at_cycle_ = -1;
  bool throw_in_activate_ = false;
  bool throw_in_deactivate_ = false;
  int dof_ = 0;
  bool hold_at_activation_ = false;
  bool differentiate_ = false;
  signal::Differentiator<JointVector> differentiator_;
  JointVector hold_, velocity_;
};

}  // namespace hapticd::test_plugins
