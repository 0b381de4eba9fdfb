#pragma once
// The server's render port (hapticd/render_port.hpp), owned and configured by the safety supervisor
// (docs/safety.md): the passivity observer and controller on the engine port, the rendered-wrench limits (with the
// soft start's scale), and the supervisor's force of this cycle. Real-time safe: fixed-size state, no allocation.
#include <Eigen/Core>

#include "hapticd/render_port.hpp"

namespace hapticd::server {

struct RenderLimits {
  double max_force_n = 1e9;
  double max_torque_nm = 1e9;
  double max_force_rate_n_per_s = 1e12;
  double max_torque_rate_nm_per_s = 1e12;
};

// One port (3-D force and velocity): the observer's energy and the controller's damping.
class PassivityPort {
 public:
  void reset() noexcept { energy_j_ = dissipated_j_ = 0.0; }
  // `force`: what the environment applies to the device side; `velocity`: the port's velocity. Returns the force
  // to apply (with the controller's damping when on).
  Eigen::Vector3d filter(const Eigen::Vector3d& force, const Eigen::Vector3d& velocity, double dt, bool control,
                         double max_damping) noexcept;
  // Energy the device side has given to the environment since reset (negative: the environment produced energy).
  [[nodiscard]] double energy_j() const noexcept { return energy_j_; }
  [[nodiscard]] double dissipated_j() const noexcept { return dissipated_j_; }

 private:
  double energy_j_ = 0.0;
  double dissipated_j_ = 0.0;
};

class RenderGuard final : public RenderPort {
 public:
  // Not real-time: the loop period, the limits, the passivity controller (on/off and its largest damping,
  // N s/m and N m s/rad).
  void configure(double period_s, const RenderLimits& limits, bool passivity_control, double max_damping,
                 double max_rotational_damping) noexcept;
  // At a chain's activation: forgets the previous wrench (the rate limit starts from `from`) and the energies.
  void reset(const Vector6& from = Vector6::Zero()) noexcept;
  // The server's soft start: the magnitude limits are scaled by `scale` in [0, 1] this cycle.
  void set_scale(double scale) noexcept { scale_ = scale; }
  // Switches the passivity controller (the observer always runs). Loop thread only.
  void set_passivity_control(bool on) noexcept { passivity_control_ = on; }

  // RenderPort: each records that the model asked for it this cycle.
  Vector6 engine_port(const Vector6& wrench, const Vector6& port_twist) noexcept override;
  Vector6 limit(const Vector6& wrench) noexcept override;
  [[nodiscard]] Eigen::Vector3d take_safety_force() noexcept override {
    safety_force_taken_ = true;
    return safety_force_;
  }

  // The server: at the start of each cycle, with the supervisor's force before the model runs.
  void begin_cycle(const Eigen::Vector3d& safety_force) noexcept {
    limited_this_cycle_ = false;
    limit_applied_ = false;
    safety_force_taken_ = false;
    safety_force_ = safety_force;
  }
  // This cycle's record, after the model's update(): limit() was called (the wrench is limited: the server need
  // not), it changed something (the state flag render_limited), the model renders the safety force (the
  // supervisor does not add it as J^T F).
  [[nodiscard]] bool limit_applied() const noexcept { return limit_applied_; }
  [[nodiscard]] bool limited_this_cycle() const noexcept { return limited_this_cycle_; }
  [[nodiscard]] bool safety_force_taken() const noexcept { return safety_force_taken_; }

  [[nodiscard]] bool passivity_control() const noexcept { return passivity_control_; }
  [[nodiscard]] double port_energy_j() const noexcept { return linear_.energy_j() + angular_.energy_j(); }
  [[nodiscard]] double dissipated_j() const noexcept { return linear_.dissipated_j() + angular_.dissipated_j(); }

 private:
  double dt_ = 1e-3;
  RenderLimits limits_;
  bool passivity_control_ = false;
  double max_damping_ = 0.0, max_rotational_damping_ = 0.0;
  PassivityPort linear_, angular_;
  double scale_ = 1.0;
  Vector6 last_ = Vector6::Zero();
  bool limited_this_cycle_ = false;
  bool limit_applied_ = false;
  bool safety_force_taken_ = false;
  Eigen::Vector3d safety_force_ = Eigen::Vector3d::Zero();
};

}  // namespace hapticd::server
