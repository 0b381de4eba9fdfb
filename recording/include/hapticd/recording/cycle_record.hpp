#pragma once
// One device's cycle as the recording keeps it (docs/recording.md): fixed size, copied through the recorder's
// lock-free ring without allocating. Poses are position then quaternion (x y z qw qx qy qz), twists and wrenches
// linear then angular, all in the world frame at the handle point.
#include <cstdint>

#include "hapticd/cycle_time.hpp"
#include "hapticd/joint_vector.hpp"
#include "hapticd/spatial.hpp"

namespace hapticd::recording {

struct CycleRecord {
  std::uint64_t cycle = 0;
  std::int64_t time_ns = 0;  // the cycle's time on the loop clock
  std::uint16_t device = 0;  // index into the recording's devices
  std::uint8_t dof = 0;
  std::uint8_t mode = 0;     // DeviceMode (hapticd/state_flags.hpp)
  std::uint32_t flags = 0;   // state_flag bits
  std::uint16_t scheme = 0;  // index into the device's schemes
  double position[kMaxJoints] = {};
  double velocity[kMaxJoints] = {};         // the server's estimate
  double torque_command[kMaxJoints] = {};   // written to the drives (after the safety supervisor)
  double torque_measured[kMaxJoints] = {};  // the device's effort (joint torque sensors, else its drive torque)
  double handle_pose[7] = {};
  double handle_twist[6] = {};
  std::uint32_t buttons = 0;          // the handle's buttons (bit i: button i pressed)
  double gripper = 0.0;               // the gripper's opening (rad; 0 without one)
  double operator_wrench[6] = {};     // the operator's wrench on the handle
  double environment_wrench[6] = {};  // what the virtual model rendered
  double sensor_wrench[6] = {};       // the force/torque sensor's reading, sensor frame (zero without a sensor)
  double target_pose[7] = {};         // the chain's desired pose
  double engine_weight = 0.0;         // 1: fresh engine input applied, 0..1 fading, 0 none
  std::uint64_t engine_sequence = 0;  // the engine input in effect (its serial number; 0 none)
  double engine_proxy_pose[7] = {};   // ... its proxy pose (zeros when it sent none)
  double engine_wrench[6] = {};       // ... and its wrench (zeros when it sent none)
  std::int64_t lateness_ns = 0;       // the loop woke this late for the cycle
  std::int64_t compute_ns = 0;        // from the cycle's start to this device's torque written
};

// A record's fields from the SDK's types (the server's recorder and hapticctl's recording of DDS states):
// a pose as x y z qw qx qy qz; a twist or wrench as its linear then angular part; joints, the rest zero.
inline void put(double (&out)[7], const Pose& p) noexcept {
  for (int a = 0; a < 3; ++a) out[a] = p.position[a];
  out[3] = p.orientation.w();
  out[4] = p.orientation.x();
  out[5] = p.orientation.y();
  out[6] = p.orientation.z();
}
inline void put(double (&out)[6], const Eigen::Vector3d& linear, const Eigen::Vector3d& angular) noexcept {
  for (int a = 0; a < 3; ++a) {
    out[a] = linear[a];
    out[3 + a] = angular[a];
  }
}
inline void put(double (&out)[kMaxJoints], const JointVector& v, int dof) noexcept {
  const int n = dof < static_cast<int>(v.size()) ? dof : static_cast<int>(v.size());
  for (int i = 0; i < n; ++i) out[i] = v[i];
  for (int i = n; i < kMaxJoints; ++i) out[i] = 0.0;
}

}  // namespace hapticd::recording
