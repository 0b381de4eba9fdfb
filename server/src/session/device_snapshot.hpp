#pragma once
// What the loop tells the outside world about a device after a cycle: a fixed-size copy handed over lock-free
// (LatestValue) to the DDS bridge, which publishes it as the device state, and to the live view. Copying it
// never allocates.
#include <cstdint>

#include "hapticd/joint_vector.hpp"
#include "hapticd/spatial.hpp"
#include "safety/device_fault.hpp"

namespace hapticd::server {

struct DeviceSnapshot {
  std::uint64_t cycle = 0;
  std::int64_t time_ns = 0;  // the cycle's time on the loop clock
  Pose handle_pose;
  Twist handle_twist;
  Wrench operator_wrench;                  // world, at the handle
  Wrench environment_wrench;               // what the virtual model renders (walls, engine)
  Pose target_pose;                        // the chain's desired pose
  JointVector position, velocity, torque;  // torque: commanded
  std::uint32_t buttons = 0;               // the handle's buttons (bit i: button i)
  double gripper = 0.0;                    // the gripper's opening (rad)
  DeviceFault fault{};
  const char* fault_reason = nullptr;  // the device's reason (static text of the plugin), nullptr if none
  std::uint64_t faults = 0;            // faults raised so far (a stop while already safe counts too)
  bool estop = false;
  bool stopping = false;  // shutdown ramp running
  bool saturated = false;
  bool switching = false;             // a scheme switch ramp is running
  int scheme = 0;                     // index into the device's schemes
  double engine_weight = 0.0;         // 1: fresh engine input applied; between 0 and 1: fading
  bool engine_stale = false;          // the engine missed its deadline
  std::uint64_t engine_sequence = 0;  // the engine input the loop applied this cycle
  bool engine_has_proxy = false;      // the engine input in effect: its proxy pose ...
  Pose engine_proxy_pose;
  bool engine_has_wrench = false;  // ... and its wrench
  Wrench engine_wrench;
  bool safe_damping = false;    // in safe mode, damping phase (false once at zero torque)
  bool limit_engaged = false;   // velocity damping or a workspace wall acted
  bool render_limited = false;  // the rendered wrench was limited
  bool thermal_derating = false;
  double thermal_load = 0.0;  // largest joint thermal load (1: continuous torque for ever)
  double dissipated_j = 0.0;  // energy the passivity controller has dissipated since the chain activated
  bool passivity_control = false;
};

}  // namespace hapticd::server
