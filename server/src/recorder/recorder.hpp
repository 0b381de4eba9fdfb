#pragma once
// Records every cycle of every device to CSV without touching the loop's timing: the loop pushes fixed-size
// records into a lock-free ring, a writer thread formats and writes them. In real-time mode a full ring drops
// the record (counted); in lockstep mode the loop waits for the writer instead, so a recording is complete.
// Long format, one row per joint and cycle: cycle,time_s,device,joint,position,velocity,effort,torque_command,
// then the device's sensor wrench (sensor_fx .. sensor_tz, repeated on each joint's row)
// Numbers are printed with 17 significant digits: identical files mean bit-identical values.
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "hapticd/chain_signals.hpp"
#include "hapticd/cycle_time.hpp"
#include "recorder/spsc_ring.hpp"

namespace hapticd::server {

struct CycleRecord {
  std::uint64_t cycle = 0;
  std::int64_t time_ns = 0;
  std::uint16_t device = 0;
  std::uint8_t dof = 0;
  double position[kMaxJoints] = {};
  double velocity[kMaxJoints] = {};
  double effort[kMaxJoints] = {};
  double torque_command[kMaxJoints] = {};
  double sensor_wrench[6] = {};  // force [N] and torque [N m] in the sensor frame (zero without a sensor)
};

class Recorder {
 public:
  // Opens the file (throws std::runtime_error if it cannot) and starts the writer thread.
  Recorder(const std::filesystem::path& file, std::vector<std::string> device_names, bool wait_when_full);
  ~Recorder();
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  // Real-time safe (in real-time mode; in lockstep it may wait for the writer).
  void record(const CycleTime& cycle, std::uint16_t device, const DeviceState& state, const JointCommand& command) noexcept;
  // Not real-time safe. Writes what is queued, stops the writer and closes the file.
  void finish();

  [[nodiscard]] std::uint64_t written() const noexcept { return written_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t dropped() const noexcept { return dropped_.load(std::memory_order_relaxed); }

 private:
  void write_loop();
  void write_record(const CycleRecord& r);

  std::vector<std::string> device_names_;
  bool wait_when_full_;
  SpscRing<CycleRecord> ring_;
  std::FILE* out_ = nullptr;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> written_{0};
  std::atomic<std::uint64_t> dropped_{0};
  std::thread writer_;
};

}  // namespace hapticd::server
