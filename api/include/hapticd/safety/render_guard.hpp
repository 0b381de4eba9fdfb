#pragma once
// The safety layer's hold on what a virtual model renders, handed to the model every cycle
// (VirtualModelInput::guard) by the server, which owns and configures it (docs/safety.md):
//   - engine_port(): a time-domain passivity observer and controller (Hannaford and Ryu) on the port where the
//     rendering engine's wrench acts on the device side. The observer sums the energy the device side has given
//     to the engine's world; whenever that sum turns negative (the engine's world has produced energy, for
//     instance from its sample-and-hold or delay) the controller adds just the damping along the port velocity
//     that dissipates the excess, up to a bound. Linear and angular parts are separate ports.
//   - limit(): the limits on the rendered wrench (force and torque magnitude, and their rate of change per
//     second) applied to everything the environment renders;
//   - take_safety_force(): the supervisor's own force on the handle this cycle (workspace walls, speed damping),
//     which an admittance-type model adds to its environment force after limit() - so its inner loop does not
//     fight the walls. A model that takes it gets it; otherwise the supervisor applies it as J^T F torque.
// Models that render an engine call engine_port() on the engine's wrench and limit() on the total
// environment wrench; the server limits the task wrench of models that do not (and counts either way).
// Real-time safe: fixed-size state, no allocation.
#include <Eigen/Core>

#include "hapticd/export.hpp"

namespace hapticd {

struct RenderLimits {
  double max_force_n = 1e9;
  double max_torque_nm = 1e9;
  double max_force_rate_n_per_s = 1e12;
  double max_torque_rate_nm_per_s = 1e12;
};

// One port (3-D force and velocity): the observer's energy and the controller's damping.
class HAPTICD_API PassivityPort {
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

class HAPTICD_API RenderGuard {
 public:
  using Vector6 = Eigen::Matrix<double, 6, 1>;  // [force; torque] or [linear; angular]

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

  // The engine's wrench at the coupling port, with the port's twist.
  Vector6 engine_port(const Vector6& wrench, const Vector6& port_twist) noexcept;
  // The limited environment wrench; counts the cycles it had to change something.
  Vector6 limit(const Vector6& wrench) noexcept;

  // The supervisor's force on the handle (world) this cycle; marks it taken.
  Eigen::Vector3d take_safety_force() noexcept {
    safety_force_taken_ = true;
    return safety_force_;
  }

  // Called by the server: at the start of each cycle, and with the supervisor's force before the model runs.
  void begin_cycle() noexcept {
    limited_this_cycle_ = false;
    limit_applied_ = false;
    safety_force_taken_ = false;
  }
  void set_safety_force(const Eigen::Vector3d& force) noexcept { safety_force_ = force; }
  [[nodiscard]] bool safety_force_taken() const noexcept { return safety_force_taken_; }
  [[nodiscard]] bool limited_this_cycle() const noexcept { return limited_this_cycle_; }
  [[nodiscard]] bool limit_applied() const noexcept { return limit_applied_; }

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
  Eigen::Vector3d safety_force_ = Eigen::Vector3d::Zero();
  bool safety_force_taken_ = false;
  bool limit_applied_ = false;  // limit() ran this cycle (the model applied it itself)
};

}  // namespace hapticd
