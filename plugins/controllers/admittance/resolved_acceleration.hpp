#pragma once
// Resolved acceleration control, the inner motion loop of admittance display (CONTROL-METHODS.md section 2):
//   xdd_c = xdd_d + Kd (xd_d - xd) + Kp (x_d - x)         (orientation error as a rotation vector)
//   qdd_c = J^+ (xdd_c - dJ/dt qd)
//   tau   = M qdd_c + C qd + g - J^T F_h                   (F_h: the operator's wrench on the handle)
// Kp = w^2, Kd = 2 zeta w per translation and rotation. Acceleration feedforward and the operator-wrench
// compensation can be switched off. Uses the server's per-cycle model terms (ChainState).
#include "hapticd/controller.hpp"
#include "hapticd/model/model_data.hpp"

namespace hapticd::controllers {

class ResolvedAcceleration final : public Controller {
 public:
  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const PluginContext& context) override;
  ReturnCode activate(const ControllerInput& current, const JointCommand& last_command) noexcept override;
  ReturnCode update(const CycleTime& cycle, const ControllerInput& input, JointCommand& command) noexcept override;
  void deactivate() override {}

 private:
  int rows_ = 3;  // 3: translation only; 6: translation and rotation
  double kp_ = 0.0, kd_ = 0.0, kp_rot_ = 0.0, kd_rot_ = 0.0;
  bool acceleration_feedforward_ = true;
  bool wrench_compensation_ = true;
  double damping_ = 1e-6;  // damped least squares at singularities
  model::TaskJacobian jacobian_;
};

}  // namespace hapticd::controllers
