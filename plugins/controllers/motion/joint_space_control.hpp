#pragma once
// Joint-space inner loops of admittance display, on the joint targets of an inverse-kinematics plugin:
//   computed_torque: qdd_c = qdd_d + Kd (qd_d - qd) + Kp (q_d - q),  tau = M qdd_c + C qd + g - J^T F_h
//                    (Kp = w^2, Kd = 2 zeta w: the same error dynamics in every joint)
//   joint_pd:        tau = Kp (q_d - q) + Kd (qd_d - qd) + g       (independent joint PD, the simplest baseline)
// computed_torque adds [h], the model's sliding friction (friction_compensation, off by default).
#include "friction_parameters.hpp"
#include "hapticd/controller.hpp"
#include "hapticd/model/model_data.hpp"

namespace hapticd::controllers {

class JointSpaceControl : public Controller {
 public:
  enum class Kind { computed_torque, joint_pd };
  explicit JointSpaceControl(Kind kind) : kind_(kind) {}

  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const PluginContext& context) override;
  Outcome activate(const ControllerInput& current, const JointCommand& last_command) override;
  Outcome update(const CycleTime& cycle, const ControllerInput& input, JointCommand& command) override;
  void deactivate() override {}

 private:
  Kind kind_;
  double kp_ = 0.0, kd_ = 0.0;              // computed torque: [1/s^2], [1/s]
  double joint_kp_ = 0.0, joint_kd_ = 0.0;  // joint PD: [N m/rad], [N m s/rad]
  bool acceleration_feedforward_ = true;
  bool wrench_compensation_ = true;
  int rows_ = 3;
  SlidingFrictionTerm friction_;
};

class ComputedTorqueControl final : public JointSpaceControl {
 public:
  ComputedTorqueControl() : JointSpaceControl(Kind::computed_torque) {}
};

class JointPdControl final : public JointSpaceControl {
 public:
  JointPdControl() : JointSpaceControl(Kind::joint_pd) {}
};

}  // namespace hapticd::controllers
