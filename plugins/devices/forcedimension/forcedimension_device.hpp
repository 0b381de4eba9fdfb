#pragma once
// Force Dimension's devices (omega.3/6/7, sigma.7, delta.3/6, lambda.7) through the vendor's SDK, loaded at run
// time ("forcedimension", docs/devices.md). A handle device (hapticd/handle.hpp): read() takes the handle's
// position, orientation, linear and angular velocity, buttons and gripper; write() sets force, torque and gripper
// force in one call; brake() engages the device's electromagnetic brakes. Every failure carries the SDK's own text.
//   configure: load libdrd (or libdhd) from `sdk_path`, FORCEDIM_SDK or the library path; open the device by
//              `serial` or `index`; refuse an uncalibrated device with the vendor's message unless `calibrate`
//              asks the robotic SDK (libdrd) to calibrate it; describe it from its model's nominal figures.
//   enable:    gravity compensation (the device's, or none: never the device's and the server's both), forces
//              on, brakes off.
//   disable:   zero force, forces off, brakes on, closed.
#include <array>
#include <memory>
#include <string>

#include "dhd_api.hpp"
#include "hapticd/device.hpp"
#include "vendor_library.hpp"

namespace hapticd::plugins::forcedimension {

class ForceDimensionDevice final : public Device {
 public:
  static ParameterSchema parameter_schema();

  ~ForceDimensionDevice() override;
  void configure(const Parameters& parameters, const PluginContext& context) override;
  [[nodiscard]] const DeviceDescription& description() const override { return description_; }
  Outcome enable() override;
  Outcome read(const CycleTime& cycle, DeviceState& state) override;
  Outcome write(const CycleTime& cycle, const JointCommand& command) override;
  Outcome brake(bool on) override;
  Outcome reset_fault() override;
  void disable() override;

 private:
  // The SDK's text of its last error, kept for the fault: the first since the last enable or recovery. Two
  // buffers in turn, so a recovery never rewrites the text of the fault another thread may still be reading.
  const char* failure(const char* what) noexcept;
  void close_device() noexcept;

  std::unique_ptr<VendorLibrary> library_;
  std::unique_ptr<DhdApi> dhd_;
  char id_ = -1;
  bool open_ = false;
  bool device_gravity_ = true;
  DeviceDescription description_;
  std::array<std::array<char, 256>, 2> errors_{};
  int error_ = 0;              // the buffer in use
  bool gripper_read_ = false;  // a gripper sample since enable: its rate can be differentiated
};

}  // namespace hapticd::plugins::forcedimension
