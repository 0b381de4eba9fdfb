#pragma once
// The forcedimension plugin's side of Force Dimension's SDK: the loaded library, the open device and the SDK's own
// thread (SdkThread) on which every call to the SDK runs, each job with a deadline, so a call that hangs (a USB
// transfer that never completes) faults the device instead of holding the loop. The SDK's last error is
// per-thread, so each job reads it where it failed and keeps the text. Shared (std::shared_ptr) between the device
// and, should a job be stuck when the device goes, that thread: whatever a late call returns into stays alive.
#include <array>
#include <memory>
#include <string>

#include "dhd_api.hpp"
#include "sdk_thread.hpp"
#include "vendor_library.hpp"

namespace hapticd::plugins::forcedimension {

// One reading of the handle (the read job's result).
struct DhdReading {
  std::array<double, 3> position{}, velocity{}, angular_velocity{};
  double frame[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  unsigned buttons = 0;
  double gripper_rad = 0.0;
};

class DhdLink {
 public:
  explicit DhdLink(std::unique_ptr<VendorLibrary> library);
  // Closes a device still open: one a call opened after the server gave up on it (it returned late, on the SDK's
  // thread, which ends the link).
  ~DhdLink();
  DhdLink(const DhdLink&) = delete;
  DhdLink& operator=(const DhdLink&) = delete;

  SdkThread sdk{"hapticd-dhd"};
  std::unique_ptr<VendorLibrary> library;
  std::unique_ptr<DhdApi> dhd;
  char id = -1;
  bool open = false;

  // What the jobs read and write, set before each is posted (by the device) or by the job (results).
  bool orientation = false, gripper = false;  // the read job reads these too
  bool device_gravity = true;                 // the enable job
  bool brakes_on = true;                      // the brake job
  std::array<double, 7> force{};              // the write job: fx fy fz tx ty tz gripper
  DhdReading reading;                         // the read job's result
  bool failed = false;                        // every job: whether it failed,
  std::array<char, 256> error{};              // and why ("reading the position: <the SDK's text>")

  // The jobs, made once (posting one allocates nothing).
  SdkThread::Job read_job, write_job, brake_job, enable_job, close_job;
  // Configure's jobs (open, name, calibration) are made here, one at a time; they store into these.
  SdkThread::Job once;
  int opened = -1, device_count = 0;
  bool calibrated = true, has_gripper = false;
  std::string system_name, once_error;
  int serial_number = -1;                       // -1: not reported
  std::array<int, 4> sdk_version{-1, 0, 0, 0};  // major, minor, release, revision; -1: not reported

 private:
  // After a call: false (failed set, the SDK's text of this thread's last error kept) when `result` < 0.
  bool check(int result, const char* what) noexcept;
  void read() noexcept;
  void close() noexcept;
};

}  // namespace hapticd::plugins::forcedimension
