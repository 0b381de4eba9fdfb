#pragma once
// The safety layer's hold on what a virtual model renders (VirtualModelInput::render), implemented by the server
// (docs/safety.md):
//   - engine_port(): a time-domain passivity observer and controller (Hannaford and Ryu) on the port where the
//     rendering engine's wrench acts on the device side: whenever the engine's world has produced energy (from
//     its sample-and-hold or delay) the controller adds just the damping along the port velocity that dissipates
//     the excess, up to a bound. Linear and angular parts are separate ports.
//   - limit(): the limits on the rendered wrench (force and torque magnitude, and their rate of change) applied to
//     everything the environment renders.
//   - take_safety_force(): the supervisor's own force on the handle this cycle (workspace walls, speed damping),
//     which an admittance-type model adds to its environment force after limit(), so its inner loop does not
//     fight the walls.
// The port records what the model did with it, the server reads that after update(): a model that called
// limit() this cycle has limited its wrench itself (otherwise the server limits TaskTarget::wrench), and one that
// took the safety force renders it (otherwise the supervisor applies that force as J^T F torque). Call them only
// for what you render. Real-time safe: no allocation.
#include <Eigen/Core>

namespace hapticd {

class RenderPort {
 public:
  using Vector6 = Eigen::Matrix<double, 6, 1>;  // [force; torque] or [linear; angular]

  // The engine's wrench at the coupling port, given the port's twist; returns the wrench to render.
  virtual Vector6 engine_port(const Vector6& wrench, const Vector6& port_twist) noexcept = 0;
  // The environment wrench within the limits; the port records that this cycle's wrench was limited.
  virtual Vector6 limit(const Vector6& wrench) noexcept = 0;
  // The supervisor's force on the handle (world) this cycle; the port records that the model renders it.
  [[nodiscard]] virtual Eigen::Vector3d take_safety_force() noexcept = 0;

 protected:
  ~RenderPort() = default;
};

}  // namespace hapticd
