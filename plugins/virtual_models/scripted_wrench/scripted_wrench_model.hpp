#pragma once
// The scripted wrench model ("scripted_wrench"): a desired wrench played over time (WrenchScript: constant,
// sine, chirp, steps) that impedance and admittance display both take, the excitation of the evaluation
// suite's force experiments (the thesis's dynamic force precision, docs/evaluation.md).
//   display: impedance   the script is the wrench the device displays (TaskTarget::wrench), plus the walls and the
//                        workspace spring of the admittance parameters on the measured handle motion (the
//                        evaluation suite's Z-width walls) and, with `coupling: true`, the rendering engine's
//                        coupling to its proxy and its wrench (an engine's motion commands are not rendered:
//                        there is no virtual body to move); the other admittance parameters are not used
//   display: admittance  a virtual admittance (every parameter of the `admittance` model) renders the script as
//                        the environment's wrench on its virtual body: M xdd + D xd = F_operator + F_script
// In both the script is the wrench the environment applies to the operator; it passes the rendered-wrench
// limits of the safety layer. The clock starts at the model's first cycle.
#include "hapticd/virtual_model.hpp"
#include "virtual_admittance.hpp"
#include "wrench_script.hpp"

namespace hapticd::models {

class ScriptedWrenchModel final : public VirtualModel {
 public:
  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const PluginContext& context) override;
  Outcome activate(const VirtualModelInput& current) override;
  Outcome update(const CycleTime& cycle, const VirtualModelInput& input, TaskTarget& target) override;
  void deactivate() override {}
  // The virtual admittance's tunable parameters (in impedance display its wall stiffness and damping count).
  void tune(const Parameters& parameters) override;

 private:
  WrenchScript script_;
  bool admittance_display_ = false;
  VirtualAdmittance admittance_;
  bool started_ = false;
  std::int64_t start_ns_ = 0;
};

}  // namespace hapticd::models
