#pragma once
// Resolved acceleration control, the inner motion loop of admittance display ([U06] methods 2):
//   xdd_c = xdd_d + Kd (xd_d - xd) + Kp (x_d - x)         (TaskMotionLaw)
//   qdd_c = J^+ (xdd_c - dJ/dt qd)
//   tau   = M qdd_c + C qd + [h] + g - J^T F_h             (F_h: the operator's wrench on the handle)
// [h]: the model's sliding friction (friction_compensation, off by default; SlidingFrictionTerm).
// Uses the server's per-cycle model terms (ChainState).
#include "friction_parameters.hpp"
#include "hapticd/controller.hpp"
#include "task_motion_law.hpp"

namespace hapticd::controllers {

class ResolvedAcceleration final : public Controller {
 public:
  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const PluginContext& context) override;
  Outcome activate(const ControllerInput& current, const JointCommand& last_command) override;
  Outcome update(const CycleTime& cycle, const ControllerInput& input, JointCommand& command) override;
  void deactivate() override {}
  // The motion law's bandwidths and damping ratio, applied at the next cycle.
  void tune(const Parameters& parameters) override { law_.tune(parameters); }

 private:
  TaskMotionLaw law_;
  SlidingFrictionTerm friction_;
  double damping_ = 1e-6;  // damped least squares at singularities
};

}  // namespace hapticd::controllers
