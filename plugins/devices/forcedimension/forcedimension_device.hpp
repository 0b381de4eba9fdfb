#pragma once
// Force Dimension's devices (omega.3/6/7, sigma.7, delta.3/6, lambda.7) through the vendor's SDK, loaded at run
// time ("forcedimension", docs/devices.md). A handle device (hapticd/handle.hpp): read() takes the handle's
// position, orientation, linear and angular velocity, buttons and gripper; write() sets force, torque and gripper
// force in one call; brake() engages the device's electromagnetic brakes. Every failure carries the SDK's own text.
// Every SDK call runs on the SDK's own thread (DhdLink, SdkThread) with a deadline: read() waits for its reading at
// most `call_deadline_ms`, write() for the force's call the same; a call that has not returned by then faults the
// device naming the call, and the loop goes on. Configure's open and calibration have deadlines of their own
// (`open_timeout_s`, `calibration_timeout_s`).
//   configure: load libdrd (or libdhd) from `sdk_path`, FORCEDIM_SDK or the library path; open the device by
//              `serial` or `index`; refuse an uncalibrated device with the vendor's message unless `calibrate`
//              asks the robotic SDK (libdrd) to calibrate it; describe it from its model's nominal figures.
//   enable:    gravity compensation (the device's, or none: never the device's and the server's both), forces
//              on, brakes off.
//   disable:   zero force, forces off, brakes on, closed.
#include <array>
#include <memory>
#include <string>

#include "dhd_link.hpp"
#include "failure_text.hpp"
#include "hapticd/device.hpp"

namespace hapticd::plugins::forcedimension {

class ForceDimensionDevice final : public Device {
 public:
  static ParameterSchema parameter_schema();

  ~ForceDimensionDevice() override;
  void configure(const Parameters& parameters, const PluginContext& context) override;
  [[nodiscard]] const DeviceDescription& description() const override { return description_; }
  Outcome enable() override;
  Outcome read(const CycleTime& cycle, DeviceState& state) override;
  Outcome write_handle(const CycleTime& cycle, const HandleCommand& command) override;
  Outcome brake(bool on) override;
  Outcome reset_fault() override;
  void disable() override;

 private:
  // The reason of a fault, kept: the first since the last enable or recovery. Two buffers in turn, so a recovery
  // never rewrites the text of the fault another thread may still be reading.
  const char* failure(const char* text) noexcept;
  // The fault of a job that missed its deadline: the SDK call it is stuck in, and for how long.
  const char* stuck() noexcept;
  // The loop: `job` posted once the previous one has finished (within its deadline; its failure told first) and
  // waited for. A failure: the SDK's, or stuck().
  Outcome run_job(const SdkThread::Job& job, std::int64_t next_post_ns = 0) noexcept;
  // A failure of the last job not told yet (told once).
  Outcome reported() noexcept;
  // Configure: `job` (link_->once) run with a deadline of `seconds`; throws DeviceUnavailable naming `call` when
  // it does not return in time.
  void run_once(const char* call, const char* timeout_key, double seconds);
  void close_device() noexcept;

  std::shared_ptr<DhdLink> link_;
  std::int64_t deadline_ns_ = 20'000'000;
  std::int64_t posted_ns_ = 0;  // when the last job was posted
  std::int64_t read_ns_ = 0;    // when this cycle's reads were posted
  std::int64_t period_ns_ = 500'000;
  DeviceDescription description_;
  FailureText<256> failure_text_;
  bool gripper_read_ = false;  // a gripper sample since enable: its rate can be differentiated
};

}  // namespace hapticd::plugins::forcedimension
