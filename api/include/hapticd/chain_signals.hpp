#pragma once
// The signals that flow along one device's plugin chain in a cycle:
//   device.read -> DeviceState -> virtual model -> TaskTarget -> inverse kinematics -> JointTarget
//   -> controller -> JointCommand -> safety -> device.write
// All members are fixed-size: copying or filling them never allocates.
#include <cstdint>

#include "hapticd/handle.hpp"
#include "hapticd/joint_vector.hpp"
#include "hapticd/spatial.hpp"

namespace hapticd {

class RenderPort;
class RedundancyResolution;

// One sample read from a device.
struct DeviceState {
  std::int64_t timestamp_ns = 0;  // device time of the sample (simulated devices: the cycle time)
  // Positions as measured; effort = joint torque. The velocity: what the device reports (reports_joint_velocity),
  // and in the chain's inputs always the server's one joint-velocity estimate - the device's own, or its positions
  // differentiated and filtered (docs/architecture.md) - the velocity every plugin, recording and client sees.
  JointState joints;
  Wrench sensor_wrench;  // force/torque sensor reading in the sensor frame, if the device has one
  // Proper acceleration (an accelerometer's reading: acceleration minus gravity) and angular acceleration of
  // the sensor in its frame [m/s^2, rad/s^2], if the sensor measures them (reports_sensor_acceleration).
  Twist sensor_acceleration;
  // The force/torque sensor reached its range this sample (a reading at the range is not a measurement): the
  // server faults the device (sensor_saturation).
  bool sensor_saturated = false;
  // A handle device's sample (hapticd/handle.hpp; base frame): the plugin fills it, the server the axes in
  // `joints` from it. Buttons and gripper of any device.
  HandleState handle;
};

// What the virtual model asks of the chain. Admittance-type models fill the motion (desired pose, twist and
// acceleration of the handle); impedance-type models fill the wrench to display.
struct TaskTarget {
  Pose pose;
  Twist twist;
  Twist acceleration;
  Wrench wrench;
  bool has_motion = false;
  bool has_wrench = false;
};

// Desired joint motion from the inverse kinematics.
struct JointTarget {
  JointVector position;
  JointVector velocity;
  JointVector acceleration;
  bool valid = false;

  void resize(int dof) {
    position.setZero(dof);
    velocity.setZero(dof);
    acceleration.setZero(dof);
    valid = false;
  }
};

// Joint torques at the joint output [N m] (forces [N] for prismatic joints) sent to the drives.
struct JointCommand {
  JointVector torque_nm;
};

struct ChainState;   // chain_state.hpp
struct EngineInput;  // engine_input.hpp

// Each input carries the device sample (with the one joint-velocity estimate) and the server's per-cycle model
// terms (chain.model is null when the device has no robot model).
struct VirtualModelInput {
  const DeviceState& device;
  const ChainState& chain;
  // The rendering engine's newest input for this device (has_proxy, has_wrench and has_motion say whether
  // anything has arrived; weight how fresh it is).
  const EngineInput& engine;
  // The safety layer's hold on what the model renders (render_port.hpp): a model that renders an engine passes
  // the engine's wrench through engine_port() and its environment wrench through limit(); the port records what
  // it was asked.
  RenderPort& render;
};

struct InverseKinematicsInput {
  const DeviceState& device;
  const TaskTarget& task;
  const ChainState& chain;
};

struct ControllerInput {
  const DeviceState& device;
  const TaskTarget& task;
  const JointTarget& joints;
  const ChainState& chain;
  // The chain's inverse kinematics' redundancy resolution at the measured state (redundancy_resolution.hpp),
  // nullptr when it offers none: task-space controllers then use the minimum-norm solution.
  RedundancyResolution* redundancy;
};

}  // namespace hapticd
