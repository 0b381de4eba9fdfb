#pragma once
// 3D Systems' Touch and Touch X (and the PHANTOM devices of the same API) through OpenHaptics' HD API, loaded at
// run time ("openhaptics", docs/devices.md). A handle device (hapticd/handle.hpp) whose SDK owns the servo loop:
// the HD scheduler calls a callback at its rate, which reads the handle in a frame (hdBeginFrame .. hdEndFrame),
// hands the sample to the loop and ticks the device's clock (`server.clock: device`), then writes the force.
//   configure: load libHD from `sdk_path`, OH_SDK_BASE or the library path; open the device by its configured
//              name (hdInitDevice; "" the default device); update a calibration that needs only an update,
//              refuse one that needs the user (the inkwell) with the vendor's word; set the scheduler's rate to
//              the session's; describe it from the device's own figures (workspace, nominal force, stiffness).
//   enable:    forces on, the callback scheduled, the scheduler started (once for every device of the process);
//              the first sample awaited (1 s).
//   read:      the newest sample of the callback (hold when none came since; one older than `max_sample_age_s` -
//              a scheduler that stopped calling - and a frame's SDK errors are faults with the vendor's text of
//              each error on the HD error stack); the joint and gimbal angles as the handle's linkage.
//   write:     the force (and the torque, where the device has 6-DOF output) for the callback. When the device
//              clocks the loop, the callback waits for the loop's force of its own tick (bounded:
//              `command_wait_us`); a late one is held for `hold_ticks` ticks, then the callback writes zero.
//   disable:   the callback ends, zero force, forces off, the scheduler stopped (by the last device), closed.
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "hapticd/device.hpp"
#include "hd_api.hpp"
#include "servo_handoff.hpp"
#include "vendor_library.hpp"

namespace hapticd::plugins::openhaptics {

// The HD error stack as a frame left it: the first errors popped (the newest first) and how many there were.
struct HdErrors {
  std::array<HDErrorInfo, 3> first{};
  int count = 0;
  void add(const HDErrorInfo& e) noexcept {
    if (count < static_cast<int>(first.size())) first[static_cast<std::size_t>(count)] = e;
    ++count;
  }
  // Pops the stack (at most 16: a bounded frame) into this.
  void drain(const HdApi& hd) noexcept;
  // The stack as it is now, popped.
  [[nodiscard]] static HdErrors of(const HdApi& hd) noexcept;
};

// One frame of the callback, for the loop.
struct HdSample {
  std::int64_t time_ns = 0;  // CLOCK_MONOTONIC, when the callback took it
  std::array<double, 3> position_mm{};
  std::array<double, 3> velocity_mm_s{};
  std::array<double, 16> transform{};  // column-major, translation in mm
  std::array<double, 3> angular_velocity{};
  std::array<double, 3> joint_angles{};   // rad
  std::array<double, 3> gimbal_angles{};  // rad
  int buttons = 0;
  HdErrors errors;  // the stack after this frame's reads (and the previous frame's end)
};

// The loop's force (and torque, on a device with 6-DOF output) for the callback.
struct HdCommand {
  std::array<double, 3> force_n{};
  std::array<double, 3> torque_mnm{};
};

class OpenHapticsDevice final : public Device {
 public:
  static ParameterSchema parameter_schema();

  ~OpenHapticsDevice() override;
  void configure(const Parameters& parameters, const PluginContext& context) override;
  [[nodiscard]] const DeviceDescription& description() const override { return description_; }
  Outcome enable() override;
  Outcome read(const CycleTime& cycle, DeviceState& state) override;
  Outcome write(const CycleTime& cycle, const JointCommand& command) override;
  Outcome reset_fault() override;
  void disable() override;
  DeviceClock* clock() noexcept override { return handoff_.clock(); }

  // The HD scheduler's thread, once per tick.
  HDCallbackCode servo() noexcept;

 private:
  const char* failure(const char* what, const HdErrors& errors) noexcept;
  void close_device() noexcept;

  std::unique_ptr<VendorLibrary> library_;
  std::unique_ptr<HdApi> hd_;
  HHD handle_ = kInvalidHandle;
  DeviceDescription description_;

  // Callback <-> loop.
  ServoHandoff<HdSample, HdCommand> handoff_;
  std::atomic<bool> running_{false};  // the callback continues while set
  std::atomic<bool> ended_{false};    // the callback wrote its last frame
  HDSchedulerHandle callback_ = 0;
  bool scheduled_ = false;
  HdCommand applied_;    // the callback's: the force it writes
  HdErrors end_errors_;  // the callback's: the previous frame's end, for the next sample

  // Loop.
  HdSample sample_;
  bool have_sample_ = false;
  std::array<std::array<char, 384>, 2> errors_{};
  int error_ = 0;
};

}  // namespace hapticd::plugins::openhaptics
