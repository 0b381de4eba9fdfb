#pragma once
// One device and its plugin chain: device.read -> virtual model -> inverse kinematics -> controller ->
// output checks -> device.write, once per cycle. Every plugin output is checked (return code, finite) before
// it can reach a motor; torques are clamped to the joints' peak torque. A failure puts this device, and only
// this device, in its safe state (zero torque) until the session ends.
#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <memory>

#include "hapticd/chain_state.hpp"
#include "hapticd/model/model_data.hpp"
#include "hapticd/model/robot_model.hpp"
#include "hapticd/plugin.hpp"
#include "hapticd/signal/differentiator.hpp"
#include "plugins/plugin_loader.hpp"

namespace hapticd::server {

enum class DeviceFault : std::uint8_t {
  none,
  device_read,
  device_write,
  non_finite_measurement,
  activation,
  virtual_model,
  inverse_kinematics,
  controller,
  non_finite_output,
};

[[nodiscard]] std::string_view to_string(DeviceFault fault) noexcept;

struct DeviceChain {
  PluginInstance<Device> device;
  std::optional<PluginInstance<VirtualModel>> virtual_model;
  std::optional<PluginInstance<InverseKinematics>> inverse_kinematics;
  PluginInstance<Controller> controller;
};

class DeviceSession {
 public:
  // The device must be configured (its description is read here); the other plugins configured too.
  DeviceSession(std::string name, DeviceChain chain);
  DeviceSession(const DeviceSession&) = delete;
  DeviceSession& operator=(const DeviceSession&) = delete;

  // Not real-time safe. Powers the device; the chain activates in the first cycle from the first sample.
  void activate();
  // Real-time safe. torque_scale in [0, 1] ramps the output (shutdown).
  void cycle(const CycleTime& cycle, double torque_scale) noexcept;
  // Not real-time safe. Zero torque, chain and device off.
  void deactivate();

  [[nodiscard]] const std::string& name() const noexcept { return name_; }
  [[nodiscard]] const DeviceDescription& description() const noexcept { return description_; }
  [[nodiscard]] const DeviceChain& chain() const noexcept { return chain_; }
  // Readable from any thread.
  [[nodiscard]] DeviceFault fault() const noexcept { return fault_.load(std::memory_order_acquire); }
  [[nodiscard]] std::uint64_t fault_cycle() const noexcept { return fault_cycle_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t saturated_cycles() const noexcept { return saturated_cycles_.load(std::memory_order_relaxed); }
  // Loop thread only (or after the loop has stopped).
  [[nodiscard]] const DeviceState& state() const noexcept { return state_; }
  [[nodiscard]] const JointCommand& command() const noexcept { return command_; }
  [[nodiscard]] const ChainState& chain_state() const noexcept { return chain_state_; }

 private:
  void enter_safe_state(DeviceFault fault, const CycleTime& cycle) noexcept;
  void write_zero_torque(const CycleTime& cycle) noexcept;
  ReturnCode activate_chain(const CycleTime& cycle) noexcept;
  void update_chain_state(bool first_cycle) noexcept;
  DeviceFault run_chain(const CycleTime& cycle) noexcept;

  std::string name_;
  DeviceChain chain_;
  DeviceDescription description_;
  JointVector torque_limit_nm_;

  DeviceState state_;
  TaskTarget task_;
  JointTarget joint_target_;
  JointCommand command_;
  JointCommand zero_command_;
  bool chain_active_ = false;

  // Per-cycle model terms shared by the chain (when the device names a robot model).
  std::unique_ptr<model::RobotModel> robot_;
  std::unique_ptr<model::ModelData> model_data_;
  int sensor_frame_ = -1;
  signal::Differentiator<JointVector> differentiator_;
  ChainState chain_state_;
  // Cut-off of the joint-velocity estimate for devices without velocity measurement (encoder differences).
  static constexpr double kVelocityFilterHz = 100.0;

  std::atomic<DeviceFault> fault_{DeviceFault::none};
  std::atomic<std::uint64_t> fault_cycle_{0};
  std::atomic<std::uint64_t> saturated_cycles_{0};
};

}  // namespace hapticd::server
