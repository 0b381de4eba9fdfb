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
// Every call but the callback's runs on the SDK's own thread (HdLink, SdkThread) with a deadline: opening and
// configure's queries `open_timeout_s`, enable 2 s, disable 1 s; a call that does not return in time is named in the
// error (configure, enable) and left to its thread (disable).
#include <array>
#include <memory>

#include "failure_text.hpp"
#include "hapticd/device.hpp"
#include "hd_link.hpp"

namespace hapticd::plugins::openhaptics {

class OpenHapticsDevice final : public Device {
 public:
  static ParameterSchema parameter_schema();

  ~OpenHapticsDevice() override;
  void configure(const Parameters& parameters, const PluginContext& context) override;
  [[nodiscard]] const DeviceDescription& description() const override { return description_; }
  Outcome enable() override;
  Outcome read(const CycleTime& cycle, DeviceState& state) override;
  Outcome write_handle(const CycleTime& cycle, const HandleCommand& command) override;
  Outcome reset_fault() override;
  void disable() override;
  DeviceClock* clock() noexcept override { return link_ ? link_->handoff.clock() : nullptr; }

 private:
  const char* failure(const char* what, const HdErrors& errors) noexcept;
  // Configure: link_->once run with a deadline of `seconds`; throws DeviceUnavailable naming the call it is stuck
  // in when it does not return in time.
  void run_once(const char* timeout_key, double seconds);
  void close_device() noexcept;

  std::shared_ptr<HdLink> link_;
  DeviceDescription description_;

  // Loop.
  HdSample sample_;
  bool have_sample_ = false;
  FailureText<384> failure_text_;
};

}  // namespace hapticd::plugins::openhaptics
