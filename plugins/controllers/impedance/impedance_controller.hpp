#pragma once
// Impedance control with force feedback (CONTROL-METHODS.md section 1):
//   tau = J^T ( F_d + Kp e + Kd de/dt ) + g(q),   e = F_d - f,   f = -F_h
// F_d: the wrench the virtual environment applies to the operator (TaskTarget::wrench; zero in free space),
// f: the wrench the device applies to the operator, measured as the opposite of the sensor's operator wrench
// F_h. force_gain = 0 is open-loop impedance control. Gyroscopic terms are deliberately not compensated.
// Optional notch sections on the commanded torque against the joint resonance (thesis: two in series,
// (s^2 + 2 0.01 w0 s + w0^2) / (s^2 + 2 0.2 w0 s + w0^2)).
// Optional model-based friction compensation of sliding friction (spec 1, friction model):
//   h = s(qd) (p0 + p1|qd| + .. + p4|qd|^4 + a2 t^2 + a1 |t| + a0),  t = g + J^T(-F_h) the static load torque,
// with s(qd) = clamp(qd / v_s, -1, 1) a smooth sign (no chatter from quantised velocities), the polynomial held
// constant beyond the highest identified velocity, and a compensation fraction below 1 against
// over-compensation. Friction at rest is left to the stiction compensator.
#include "hapticd/controller.hpp"
#include "hapticd/model/model_data.hpp"
#include <array>

#include "hapticd/signal/biquad.hpp"
#include "hapticd/signal/differentiator.hpp"

namespace hapticd::controllers {

class ImpedanceController final : public Controller {
 public:
  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const PluginContext& context) override;
  ReturnCode activate(const ControllerInput& current, const JointCommand& last_command) noexcept override;
  ReturnCode update(const CycleTime& cycle, const ControllerInput& input, JointCommand& command) noexcept override;
  void deactivate() override {}

 private:
  using Vector6 = Eigen::Matrix<double, 6, 1>;
  [[nodiscard]] Vector6 force_error(const ControllerInput& input) const noexcept;

  int rows_ = 3;
  double kp_ = 0.0, kd_ = 0.0;
  bool gravity_compensation_ = true;
  signal::Differentiator<Vector6> error_rate_;
  static constexpr int kMaxNotches = 4;
  std::array<signal::Biquad<JointVector>, kMaxNotches> notches_{};
  int notch_count_ = 0;
  bool friction_compensation_ = false;
  std::array<double, 5> friction_p_{};
  std::array<double, 3> friction_load_{};
  double friction_velocity_max_ = 5.0, friction_smooth_velocity_ = 0.05, friction_fraction_ = 0.8;
  [[nodiscard]] double friction(double velocity, double load) const noexcept;
};

}  // namespace hapticd::controllers
