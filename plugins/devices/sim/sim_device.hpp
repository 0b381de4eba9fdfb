#pragma once
#include <atomic>
// The simulated device plugin ("sim"): any serial URDF chain with drive data, ViSHaRD3/6/10 included.
// Physics in substeps well above the control rate (FlexibleChain), drives (current loop, saturation, thermal
// limit, speed monitoring), sensing as on the hardware (motor encoders, force/torque sensor), and what is
// attached to the handle (HandleAttachment), switchable at run time through request_attachment().
// Ground truth is kept apart from the device outputs, for tests and evaluations.
#include <array>
#include <memory>

#include "drive.hpp"
#include "environment_wall.hpp"
#include "flexible_chain.hpp"
#include "force_sensor.hpp"
#include "handle_attachment.hpp"
#include "hapticd/device.hpp"
#include "hapticd/realtime/latest_value.hpp"

namespace hapticd::sim {

// The simulation's true state after the last read(), never mixed into the device outputs.
struct GroundTruth {
  JointVector link_position, link_velocity, motor_position, motor_velocity;
  JointVector spring_torque, friction_torque, motor_torque;
  Eigen::Isometry3d handle_pose = Eigen::Isometry3d::Identity();
  Vector6d handle_twist = Vector6d::Zero();         // [linear; angular], world
  Vector6d handle_wrench = Vector6d::Zero();        // applied to the handle by the attachment, world
  Vector6d sensor_wrench = Vector6d::Zero();        // the same in the sensor frame, before the sensor's effects
  Vector6d sensor_acceleration = Vector6d::Zero();  // proper linear and angular acceleration, sensor frame
  double time_s = 0.0;
  bool sensor_saturated = false;
  int overspeed_joint = -1;  // first joint above its speed limit, -1 if none
};

class SimDevice final : public Device {
 public:
  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const PluginContext& context) override;
  [[nodiscard]] const DeviceDescription& description() const override { return description_; }
  // Starts the simulation at its initial position (the brakes, if any, released).
  Outcome enable() override;
  // With `homing`: the encoders' reference found; positions are absolute from now on.
  Outcome home() override;
  Outcome read(const CycleTime& cycle, DeviceState& state) override;
  Outcome write(const CycleTime& cycle, const JointCommand& command) override;
  // Clears the speed monitor's latch once every joint is below its limit again.
  Outcome reset_fault() override;
  void disable() override;
  // "operator.push" {fx, fy, fz[, ramp_s = 0.5]}: the simulated operator takes the handle (if it was not
  // holding it) and ramps its voluntary force to that value; "operator.release": lets go of the handle;
  // "operator.grasp" {0..1}: loose .. firm.
  RuntimeReply handle_request(std::string_view name, const std::vector<double>& values) override;

  // Any thread: replaces what is attached to the handle from the next substep on.
  void request_attachment(const AttachmentSettings& settings) { attachment_requests_.publish(settings); }
  [[nodiscard]] const GroundTruth& ground_truth() const noexcept { return truth_; }
  bool simulated_truth(SimulatedTruth& out) const override;
  [[nodiscard]] const FlexibleChain& chain() const noexcept { return *chain_; }
  [[nodiscard]] double substep_s() const noexcept { return substep_s_; }

 private:
  void substep() noexcept;
  void read_accelerations(DeviceState& state) noexcept;

  DeviceDescription description_;
  std::unique_ptr<FlexibleChain> chain_;
  std::vector<Drive> drives_;
  ForceSensor sensor_;
  HandleAttachment attachment_;
  EnvironmentWall wall_;
  AttachmentSettings initial_attachment_;
  realtime::LatestValue<AttachmentSettings> attachment_requests_;
  AttachmentSettings pending_;
  AttachmentSettings requested_;                   // the last attachment asked for (request thread)
  double requested_at_s_ = 0.0;                    // ... and when (simulated time)
  std::atomic<std::int64_t> simulated_now_ns_{0};  // for requests: when "now" is
  GroundTruth truth_;
  JointVector initial_position_, command_, counts_per_rev_, speed_limits_;
  // The command's dead time (command_delay_s): written commands wait in a ring until they are due.
  struct DelayedCommand {
    std::int64_t due_ns = 0;
    JointVector torque;
  };
  static constexpr std::size_t kMaxDelayed = 16;
  std::array<DelayedCommand, kMaxDelayed> delayed_{};
  std::size_t delayed_head_ = 0, delayed_count_ = 0;
  std::int64_t command_delay_ns_ = 0;
  void apply_due_commands() noexcept;
  int handle_frame_ = -1, sensor_frame_ = -1;
  double substep_s_ = 5e-5;
  std::int64_t substep_ns_ = 50000;
  std::int64_t simulated_ns_ = 0;
  bool speed_monitor_ = true;
  bool enabled_ = false;
  bool homed_ = false;
  JointVector encoder_offset_;  // before homing: the motor positions at enable
  bool sensor_present_ = true;
  bool passive_gimbal_ = false;
  bool accelerations_ = false;
  // What the sensor carries (the URDF's links beyond its frame: a handle, a gimbal): its weight always, its
  // inertial force with "sensor_handle_inertia"; the centre's velocity one substep ago for the acceleration.
  void sensor_reading(const Eigen::Isometry3d& handle, const Vector6d& twist, const Vector6d& wrench) noexcept;
  double carried_mass_ = 0.0;
  Eigen::Vector3d carried_com_ = Eigen::Vector3d::Zero();  // sensor frame
  bool carried_inertia_ = true;
  bool carried_velocity_valid_ = false;
  Eigen::Vector3d carried_velocity_ = Eigen::Vector3d::Zero();
  bool joint_torque_sensors_ = false;
  double joint_torque_resolution_ = 0.01;
  std::array<double, 2> acceleration_range_{49.0, 100.0};
  std::array<double, 2> acceleration_resolution_{0.0981, 0.1};
};

}  // namespace hapticd::sim
