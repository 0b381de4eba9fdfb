#pragma once
// Impedance control with force feedback and the thesis's compensators ([U06] methods 1):
//   tau_d = J^T ( F_d + Kp e + Kd de/dt ) + g(q) + [friction] + [disturbance observer],  e = F_d - f,  f = -F_h
//   tau   = tau_d + Kt (tau_d - tau_joint)          (joint-torque feedback, devices with joint torque sensors)
//   tau  -> notch filters -> drives
// F_d: the wrench the virtual environment applies to the operator (TaskTarget::wrench; zero in free space);
// f: the wrench the device applies to the operator, the opposite of the sensor's operator wrench F_h.
// force_gain = 0 is open-loop impedance control. Gyroscopic terms are deliberately not compensated.
// [friction] is one of: none; sliding-friction compensation (FrictionCompensation, from the built-in curve or
// a friction file, optionally re-tuned on line by FrictionEstimator + FrictionRetuner); the variable-structure
// stiction compensator (StictionCompensator, which uses the sliding compensation while a joint moves).
// Real-time safe in activate() and update().
#include <array>
#include <memory>

#include "disturbance_observer.hpp"
#include "friction_estimator.hpp"
#include "friction_parameters.hpp"
#include "friction_retuner.hpp"
#include "hapticd/controller.hpp"
#include "hapticd/realtime/latest_value.hpp"
#include "hapticd/signal/biquad.hpp"
#include "hapticd/signal/differentiator.hpp"
#include "stiction_compensator.hpp"

namespace hapticd::controllers {

class ImpedanceController final : public Controller {
 public:
  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const PluginContext& context) override;
  Outcome activate(const ControllerInput& current, const JointCommand& last_command) override;
  Outcome update(const CycleTime& cycle, const ControllerInput& input, JointCommand& command) override;
  void deactivate() override {}
  // The tunable gains (force_gain, force_derivative_gain, joint_torque_gain), taken at the next cycle.
  void tune(const Parameters& parameters) override;

 private:
  struct Gains {
    double kp = 0.0, kd = 0.0, kt = 0.0;
  };
  // The gains, checked against what the device measures; throws ParameterError.
  [[nodiscard]] Gains gains_of(const Parameters& p) const;
  void apply(const Gains& gains) noexcept;
  using Vector6 = Eigen::Matrix<double, 6, 1>;
  [[nodiscard]] Vector6 force_error(const ControllerInput& input) const noexcept;
  void configure_friction(const Parameters& p, const PluginContext& context);
  void adapt(const CycleTime& cycle, const ControllerInput& in, const JointVector& operator_torques) noexcept;

  int dof_ = 0;
  int rows_ = 3;
  double kp_ = 0.0, kd_ = 0.0;
  bool gravity_compensation_ = true;
  signal::Differentiator<Vector6> error_rate_;
  static constexpr int kMaxNotches = 4;
  std::array<signal::Biquad<JointVector>, kMaxNotches> notches_{};
  int notch_count_ = 0;

  bool friction_compensation_ = false;
  FrictionCompensation friction_;
  bool stiction_compensation_ = false;
  StictionCompensator stiction_;
  bool disturbance_observer_ = false;
  DisturbanceObserver observer_;
  double joint_torque_gain_ = 0.0;
  bool reports_wrench_ = false, reports_joint_torque_ = false;
  realtime::LatestValue<Gains> gains_inbox_;
  Gains gains_incoming_;

  bool adaptive_ = false;
  std::uint64_t adapt_period_cycles_ = 80000;
  std::uint64_t adapt_cycles_ = 0;
  std::uint64_t adapt_sequence_ = 0;
  FrictionEstimator estimator_;
  std::unique_ptr<FrictionRetuner> retuner_;
  RetunedModels retuned_{};
  bool retuned_pending_ = false;

  JointVector sliding_, friction_torque_, projected_error_, previous_command_;
};

}  // namespace hapticd::controllers
