#include "safety/motion_limits.hpp"

#include <cmath>

#include "hapticd/model/model_data.hpp"

namespace hapticd::server {

void MotionLimits::configure(const SafetySettings& settings, const JointVector& velocity_max, bool handle_axes,
                             const Eigen::Matrix3d& base_rotation) {
  s_ = settings;
  handle_axes_ = handle_axes;
  base_rotation_ = base_rotation;
  damping_from_ = velocity_max * settings.joint_damping_from;
  fault_at_ = velocity_max * settings.joint_fault_at;
  for (int i = 0; i < 3; ++i) {
    lo_[i] = settings.workspace_min_m[static_cast<std::size_t>(i)];
    hi_[i] = settings.workspace_max_m[static_cast<std::size_t>(i)];
  }
  workspace_ = (lo_.array() < hi_.array()).all();
}

void MotionLimits::add_handle_force(const ChainState& chain, const Eigen::Vector3d& force,
                                    JointVector& torque) const noexcept {
  if (handle_axes_) {
    torque.head<3>().noalias() += base_rotation_.transpose() * force;
  } else {
    torque.noalias() += chain.data->frame_jacobian.topRows<3>().transpose() * force;
  }
}

DeviceFault MotionLimits::check(const JointVector& qd, const ChainState& chain,
                                Eigen::Vector3d& handle_force) noexcept {
  engaged_ = false;
  handle_force.setZero();
  for (int i = 0; i < qd.size(); ++i) {
    const double speed = std::abs(qd[i]);
    if (speed > fault_at_[i]) return DeviceFault::joint_velocity;
    engaged_ = engaged_ || speed > damping_from_[i];
  }
  if (!chain.has_handle) return DeviceFault::none;  // no robot model, no handle: joint limits only

  const Eigen::Vector3d& v = chain.handle_twist.linear;
  const double speed = v.norm();
  if (s_.max_speed_m_s > 0.0) {
    if (speed > s_.max_speed_m_s) return DeviceFault::cartesian_velocity;
    if (speed > s_.speed_damping_from_m_s) {
      handle_force -= s_.speed_damping_n_s_per_m * (speed - s_.speed_damping_from_m_s) * (v / speed);
      engaged_ = true;
    }
  }
  if (workspace_) {
    const Eigen::Vector3d& p = chain.handle_pose.position;
    for (int i = 0; i < 3; ++i) {
      // Depth beyond the wall, positive outwards, and the outward direction.
      double depth = 0.0, outward = 0.0;
      if (p[i] > hi_[i]) {
        depth = p[i] - hi_[i];
        outward = 1.0;
      } else if (p[i] < lo_[i]) {
        depth = lo_[i] - p[i];
        outward = -1.0;
      }
      if (depth <= 0.0) continue;
      if (depth > s_.wall_fault_depth_m) return DeviceFault::workspace;
      const double outward_speed = std::max(0.0, outward * v[i]);
      handle_force[i] -= outward * (s_.wall_stiffness_n_per_m * depth + s_.wall_damping_n_s_per_m * outward_speed);
      engaged_ = true;
    }
  }
  return DeviceFault::none;
}

void MotionLimits::apply(const JointVector& qd, const ChainState& chain, const Eigen::Vector3d& handle_force,
                         bool force_taken, JointVector& torque) noexcept {
  for (int i = 0; i < qd.size(); ++i) {
    const double speed = std::abs(qd[i]);
    if (speed > damping_from_[i])
      torque[i] -= s_.joint_damping_gain * (speed - damping_from_[i]) * std::copysign(1.0, qd[i]);
  }
  if ((chain.data != nullptr || handle_axes_) && !force_taken && !handle_force.isZero())
    add_handle_force(chain, handle_force, torque);
}

}  // namespace hapticd::server
