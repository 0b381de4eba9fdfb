#pragma once
// Variable-structure force control against static friction ([U06] methods 1, [4.22, 4.23]).
// Per joint, a relay with hysteresis on the joint velocity selects the structure:
//   moving:  the sliding-friction compensation h_i(qd_i, t_i) is added (PD force control);
//   at rest: tau0_i + I_i is added (PID force control), where tau0_i is h_i at the switching instant (no
//            jump at the switch) and I_i integrates the joint's share of the task-space force error,
//            (J^T Ki e)_i, from zero, limited to +-integrator_limit.
// The relay switches to "moving" when |qd_i| rises above moving_velocity (a few velocity quanta of the
// differentiated encoder) and back to "at rest" when |qd_i| falls below rest_velocity. Real-time safe.
#include <array>

#include "hapticd/joint_vector.hpp"

namespace hapticd::controllers {

struct StictionSettings {
  double integral_gain = 100.0;      // Ki [1/s] on the task-space force error
  double integrator_limit_nm = 2.0;  // |I_i| limit
  double moving_velocity = 0.05;     // [rad/s] relay: at rest -> moving
  double rest_velocity = 0.01;       // [rad/s] relay: moving -> at rest
};

class StictionCompensator {
 public:
  void configure(int dof, const StictionSettings& settings, double period_s) noexcept;
  // Every joint at rest, integrators and held torques zero.
  void reset() noexcept;
  // velocity: joint velocities; sliding: this cycle's sliding-friction compensation per joint (used while
  // moving); projected_error: J^T e, the force error mapped to the joints (before Ki). Writes the stiction /
  // friction torque to add per joint.
  void update(const JointVector& velocity, const JointVector& sliding, const JointVector& projected_error,
              JointVector& out) noexcept;
  [[nodiscard]] bool moving(int i) const noexcept { return moving_[static_cast<std::size_t>(i)]; }
  [[nodiscard]] double integral(int i) const noexcept { return integral_[static_cast<std::size_t>(i)]; }

 private:
  int dof_ = 0;
  StictionSettings s_;
  double period_s_ = 5e-4;
  std::array<bool, kMaxJoints> moving_{};
  std::array<double, kMaxJoints> held_{};      // tau0_i
  std::array<double, kMaxJoints> integral_{};  // I_i
  std::array<double, kMaxJoints> last_sliding_{};
};

}  // namespace hapticd::controllers
