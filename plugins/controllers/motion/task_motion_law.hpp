#pragma once
// The task-space motion law shared by the inner loops of admittance display:
//   xdd_c = [xdd_d] + Kd (xd_d - xd) + Kp (x_d - x)   (orientation error as a rotation vector)
// with Kp = w^2, Kd = 2 zeta w for translation and rotation, over 3 (translation) or 6 task rows.
#include "hapticd/chain_signals.hpp"
#include "hapticd/chain_state.hpp"
#include "hapticd/model/model_data.hpp"
#include "hapticd/parameters.hpp"
#include "hapticd/plugin_context.hpp"
#include "hapticd/realtime/latest_value.hpp"

namespace hapticd::controllers {

class TaskMotionLaw {
 public:
  // Declares task, bandwidth_rad_s, rotational_bandwidth_rad_s, damping_ratio, acceleration_feedforward,
  // wrench_compensation.
  static void declare(ParameterSchema& schema);
  void configure(const Parameters& p, const PluginContext& context);
  // Not real-time, a server thread: the tunable gains (the bandwidths and the damping ratio) for the loop, which
  // take_tuned() applies at the start of a cycle.
  void tune(const Parameters& p);
  void take_tuned() noexcept;

  // xdd_c for the target and the measured state (rows() entries used).
  [[nodiscard]] model::Vector6d acceleration(const TaskTarget& target, const ChainState& state) const noexcept;
  // -J^T F_h over the task rows when wrench compensation is on (cancels the operator's wrench), else zero.
  void add_wrench_compensation(const ChainState& state, JointVector& torque) const noexcept;

  [[nodiscard]] int rows() const noexcept { return rows_; }

 private:
  struct Gains {
    double kp = 0.0, kd = 0.0, kp_rot = 0.0, kd_rot = 0.0;
  };
  static Gains gains_of(const Parameters& p);
  void apply(const Gains& gains) noexcept;

  realtime::LatestValue<Gains> inbox_;
  Gains incoming_;
  int rows_ = 3;
  double kp_ = 0.0, kd_ = 0.0, kp_rot_ = 0.0, kd_rot_ = 0.0;
  bool acceleration_feedforward_ = true;
  bool wrench_compensation_ = true;
};

}  // namespace hapticd::controllers
