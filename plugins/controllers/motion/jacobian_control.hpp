#pragma once
// Inverse- and transposed-Jacobian control, the thesis's cheaper inner loops of admittance display
// ([U06] methods 2), with constant diagonal inertias (no coupling, no gyroscopic terms):
//   inverse_jacobian:    tau = M_hat J^+ (xdd_c - dJ/dt qd) + [h] + g - J^T F_h     (M_hat: joint space)
//   transposed_jacobian: tau = J^T Mx_hat xdd_c + [h] + g - J^T F_h                   (Mx_hat: task space)
// [h]: the model's sliding friction (friction_compensation, off by default; SlidingFrictionTerm).
// The inertias are parameters (the thesis's ViSHaRD3 workspace means: M_hat = diag(0.930, 0.416, 0.279) kg m^2,
// Mx_hat = diag(6.813, 9.350, 4.812) kg); left empty they are taken from the model at activation (the diagonal
// of M, resp. of the operational-space inertia).
#include "friction_parameters.hpp"
#include "hapticd/controller.hpp"
#include "task_motion_law.hpp"

namespace hapticd::controllers {

class JacobianControl : public Controller {
 public:
  enum class Kind { inverse, transposed };
  explicit JacobianControl(Kind kind) : kind_(kind) {}

  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const PluginContext& context) override;
  Outcome activate(const ControllerInput& current, const JointCommand& last_command) override;
  Outcome update(const CycleTime& cycle, const ControllerInput& input, JointCommand& command) override;
  void deactivate() override {}
  // The motion law's bandwidths and damping ratio, applied at the next cycle.
  void tune(const Parameters& parameters) override { law_.tune(parameters); }

 private:
  Kind kind_;
  TaskMotionLaw law_;
  SlidingFrictionTerm friction_;
  JointVector joint_inertia_;    // M_hat diagonal
  model::TaskVector task_mass_;  // Mx_hat diagonal
  bool inertia_from_model_ = true;
  double damping_ = 1e-6;
};

class InverseJacobianControl final : public JacobianControl {
 public:
  InverseJacobianControl() : JacobianControl(Kind::inverse) {}
};

class TransposedJacobianControl final : public JacobianControl {
 public:
  TransposedJacobianControl() : JacobianControl(Kind::transposed) {}
};

}  // namespace hapticd::controllers
