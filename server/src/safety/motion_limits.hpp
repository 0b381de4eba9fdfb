#pragma once
// Velocity limits and workspace walls, applied to the torque command after the controller:
//   - joint velocity: above joint_damping_from x velocity_max a joint gets damping against its excess speed;
//     above joint_fault_at x velocity_max the device faults (joint_velocity);
//   - handle speed (devices with a robot model, and handle devices): above speed_damping_from_m_s the handle gets
//   damping against
//     its excess speed (J^T F); above max_speed_m_s the device faults (cartesian_velocity);
//   - workspace walls: outside the box the handle is pushed back by a spring (and damping of outward motion),
//     J^T F; beyond wall_fault_depth_m the device faults (workspace).
// On a handle device (hapticd/handle.hpp) the handle force is added to its force axes directly (in its base frame).
// Real-time safe after configure().
#include <Eigen/Core>

#include "hapticd/chain_state.hpp"
#include "hapticd/joint_vector.hpp"
#include "safety/device_fault.hpp"
#include "safety/safety_settings.hpp"

namespace hapticd::server {

class MotionLimits {
 public:
  // handle_axes: a handle device whose first three axes are the handle's force in the base frame that
  // base_rotation turns into the world.
  void configure(const SafetySettings& settings, const JointVector& velocity_max, bool handle_axes = false,
                 const Eigen::Matrix3d& base_rotation = Eigen::Matrix3d::Identity());
  // Before the chain: checks the joint and handle speeds and the wall depth (the fault a limit raises, or none)
  // and computes the force on the handle of the speed damping and the walls (zero without a robot model).
  // qd: the joint-velocity estimate.
  DeviceFault check(const JointVector& qd, const ChainState& chain, Eigen::Vector3d& handle_force) noexcept;
  // After the controller: adds the joint damping, and the handle force as J^T F unless `force_taken` (an
  // admittance model took it into its dynamics).
  void apply(const JointVector& qd, const ChainState& chain, const Eigen::Vector3d& handle_force, bool force_taken,
             JointVector& torque) noexcept;
  // A damping or wall force acted this cycle.
  [[nodiscard]] bool engaged() const noexcept { return engaged_; }
  [[nodiscard]] bool has_workspace() const noexcept { return workspace_; }

 private:
  void add_handle_force(const ChainState& chain, const Eigen::Vector3d& force, JointVector& torque) const noexcept;

  SafetySettings s_;
  JointVector damping_from_, fault_at_;
  Eigen::Vector3d lo_ = Eigen::Vector3d::Zero(), hi_ = Eigen::Vector3d::Zero();
  bool workspace_ = false;
  bool handle_axes_ = false;
  Eigen::Matrix3d base_rotation_ = Eigen::Matrix3d::Identity();
  bool engaged_ = false;
};

}  // namespace hapticd::server
