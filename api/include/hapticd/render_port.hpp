#pragma once
// The safety layer's hold on what a virtual model renders (VirtualModelInput::render), implemented by the server
// (docs/safety.md):
//   - engine_port(): a time-domain passivity observer and controller (Hannaford and Ryu) on the port where the
//     rendering engine's wrench acts on the device side: whenever the engine's world has produced energy (from
//     its sample-and-hold or delay) the controller adds just the damping along the port velocity that dissipates
//     the excess, up to a bound. Linear and angular parts are separate ports.
//   - limit(): the limits on the rendered wrench (force and torque magnitude, and their rate of change) applied to
//     everything the environment renders.
//   - safety_force(): the supervisor's own force on the handle this cycle (workspace walls, speed damping), which
//     an admittance-type model adds to its environment force after limit(), so its inner loop does not fight
//     the walls.
// The model answers in its output: TaskTarget::wrench_limited (it called limit(); otherwise the server limits
// the task wrench) and TaskTarget::includes_safety_force (it added safety_force(); otherwise the supervisor
// applies that force as J^T F torque). Real-time safe: no allocation.
#include <Eigen/Core>

namespace hapticd {

class RenderPort {
 public:
  using Vector6 = Eigen::Matrix<double, 6, 1>;  // [force; torque] or [linear; angular]

  // The engine's wrench at the coupling port, given the port's twist; returns the wrench to render.
  virtual Vector6 engine_port(const Vector6& wrench, const Vector6& port_twist) noexcept = 0;
  // The environment wrench within the limits.
  virtual Vector6 limit(const Vector6& wrench) noexcept = 0;
  // The supervisor's force on the handle (world) this cycle.
  [[nodiscard]] virtual Eigen::Vector3d safety_force() const noexcept = 0;

 protected:
  ~RenderPort() = default;
};

}  // namespace hapticd
