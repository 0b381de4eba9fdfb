#pragma once
// What the loop tells the outside world about a device after a cycle: a fixed-size copy handed over lock-free
// (LatestValue) to the DDS bridge, which publishes it as the device state. Copying it never allocates.
#include <cstdint>

#include "hapticd/joint_vector.hpp"
#include "hapticd/spatial.hpp"

namespace hapticd::server {

enum class DeviceFault : std::uint8_t;

struct DeviceSnapshot {
  std::uint64_t cycle = 0;
  std::int64_t time_ns = 0;          // the cycle's time on the loop clock
  Pose handle_pose;
  Twist handle_twist;
  Wrench operator_wrench;            // world, at the handle
  Wrench environment_wrench;         // what the virtual model renders (walls, engine)
  Pose target_pose;                  // the chain's desired pose
  JointVector position, velocity, torque;  // torque: commanded
  DeviceFault fault{};
  bool estop = false;
  bool stopping = false;             // shutdown ramp running
  bool saturated = false;
  bool switching = false;            // a scheme switch ramp is running
  int scheme = 0;                    // index into the device's schemes
  double engine_weight = 0.0;        // 1: fresh engine input applied; between 0 and 1: fading
  bool engine_stale = false;         // the engine missed its deadline
  std::uint64_t engine_sequence = 0; // the engine input the loop applied this cycle
};

}  // namespace hapticd::server
