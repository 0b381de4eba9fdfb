#pragma once
#include <string>
#include <vector>

#include "hapticd/handle.hpp"
#include "hapticd/spatial.hpp"

namespace hapticd {

// Limits and identity of one joint, at the joint output (after the gear).
struct JointDescription {
  std::string name;
  double position_min = -1e9;         // [rad or m]
  double position_max = 1e9;          // [rad or m]
  double velocity_max = 1e9;          // [rad/s or m/s]
  double torque_peak_nm = 0.0;        // largest torque the drive may be commanded (saturation)
  double torque_continuous_nm = 0.0;  // thermally sustainable torque
};

// What the device offers beyond reading and writing (its lifecycle, docs/plugin-guide.md).
struct DeviceCapabilities {
  bool brakes = false;  // holding brakes: released by enable(), engaged by disable()
  bool homing = false;  // needs home() after enable() before its positions are absolute
};

// What a device plugin tells the server about itself after configure(). Not used in the loop (strings and
// vectors): the server copies what the loop needs into fixed-size storage.
struct DeviceDescription {
  std::string model;  // e.g. "vishard3", "test_mass_spring"
  // What the unit is, for the log at start and --check-config: its serial number when it reports one, and the
  // vendor's software the plugin drives it through - name, version, where it was found ("" for a simulation).
  std::string serial;
  std::string vendor_software;
  // Joints (a serial chain the server models from robot_model_file) or the handle (the vendor's SDK does the
  // kinematics: `handle` says what it offers, and the server sets `joints` to the handle's axes, hapticd/handle.hpp).
  DeviceInterface interface = DeviceInterface::joints;
  HandleDescription handle;  // interface == handle
  std::vector<JointDescription> joints;
  std::string handle_frame;      // name of the handle (end-effector) frame in the robot model, if any
  std::string sensor_frame;      // name of the force/torque sensor frame, if any
  std::string robot_model_file;  // URDF of the chain, if any
  bool reports_joint_velocity = false;
  bool reports_wrench = false;
  bool reports_joint_torque = false;
  bool reports_sensor_acceleration = false;
  // A simulation, not hardware: the server says so to clients and evaluations (no guess from the plugin's name).
  bool simulated = false;
  DeviceCapabilities capabilities;
  // Where the device stands: its base (the robot model's root) in the session's world frame. Set by the server
  // from the session file (`base_pose`), not by the plugin. Every pose, twist and wrench the server computes,
  // publishes and records is in the world frame.
  Pose base_pose;

  [[nodiscard]] int dof() const noexcept { return static_cast<int>(joints.size()); }
};

}  // namespace hapticd
