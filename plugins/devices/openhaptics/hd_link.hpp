#pragma once
// The openhaptics plugin's side of OpenHaptics' HD API: the loaded library, the open device, the servo callback
// the HD scheduler calls (and its hand-off to the loop), and the SDK's own thread (SdkThread) on which the plugin's
// other calls run - open, calibration, the figures, enabling, scheduling, closing - each with a deadline, so an
// SDK that hangs (a device that stops answering mid-call) cannot hold the server's start or its stop. Shared
// (std::shared_ptr) between the device and, should a call be stuck when the device goes, that thread and the
// scheduler's callback: whatever a late call returns into stays alive.
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "hd_api.hpp"
#include "sdk_thread.hpp"
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

// What configure learns from the SDK (on the SDK's thread).
struct HdFacts {
  std::string model, serial, version, driver;
  HDenum calibration = 0;
  int input_dof = 0, output_dof = 0;
  double workspace[6] = {0, 0, 0, 0, 0, 0};
  double max_force = 0, continuous = 0, stiffness = 0, damping = 0;
  double max_torque_mnm = 0, torque_stiffness = 0, torque_damping = 0;
};

class HdLink {
 public:
  explicit HdLink(std::unique_ptr<VendorLibrary> library);
  // Closes a device still open: one a call opened after the server gave up on it (it returned late, on the SDK's
  // thread, which ends the link).
  ~HdLink();
  HdLink(const HdLink&) = delete;
  HdLink& operator=(const HdLink&) = delete;

  SdkThread sdk{"hapticd-hd"};
  std::unique_ptr<VendorLibrary> library;
  std::unique_ptr<HdApi> hd;
  HHD handle = kInvalidHandle;
  bool actuated_torque = false;

  // The callback <-> the loop.
  ServoHandoff<HdSample, HdCommand> handoff;
  std::atomic<bool> running{false};  // the callback continues while set
  std::atomic<bool> ended{false};    // the callback wrote its last frame

  // Configure's and enable's jobs store here; `once` is the job being run.
  SdkThread::Job once;
  HdFacts facts;
  HdErrors errors;          // a job's SDK errors
  const char* failed = "";  // what a job was doing when the SDK raised them ("" none)
  HDSchedulerHandle callback = 0;
  bool scheduled = false;

  // The HD scheduler's thread, once per tick.
  HDCallbackCode servo() noexcept;
  // Enable's job: forces on, the callback scheduled, the scheduler started (the first device of the process).
  void start() noexcept;
  // Close's job: the callback's last frame awaited (0.1 s), unscheduled, the scheduler stopped (the last device),
  // forces off, the device closed.
  void close() noexcept;

 private:
  HdCommand applied_;    // the callback's: the force it writes
  HdErrors end_errors_;  // the callback's: the previous frame's end, for the next sample
};

}  // namespace hapticd::plugins::openhaptics
