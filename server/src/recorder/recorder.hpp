#pragma once
// Records every cycle of every device to CSV without touching the loop's timing: the loop pushes fixed-size
// records into a lock-free ring, a writer thread formats and writes them. In real-time mode a full ring drops
// the record (counted); in lockstep mode the loop waits for the writer instead, so a recording is complete.
// Long format, one row per joint and cycle: cycle,time_s,device,joint,position,velocity,effort,torque_command,
// then the device's sensor wrench (sensor_fx .. sensor_tz, repeated on each joint's row)
// Numbers are printed with 17 significant digits: identical files mean bit-identical values.
// Every write is checked. Rows are written in chunks of whole records; a write that fails (a full disk, an
// I/O error) is cut back to the last whole record (the file always ends on a whole row), the recorder stops
// writing, and every record from then on is counted as lost (failed(), error(), lost()). The data is synced
// to the disk every few megabytes and at the end; a failing sync cuts the file back to what was synced.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
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
  // Opens the file (throws std::runtime_error if it cannot) and starts the writer thread. producers: the loop
  // threads that record, each into a ring of its own (with several, rows of different loops interleave in
  // chunks: sort by cycle).
  Recorder(const std::filesystem::path& file, std::vector<std::string> device_names, bool wait_when_full,
           std::size_t producers = 1);
  ~Recorder();
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  // Real-time safe (in real-time mode; in lockstep it may wait for the writer). Only `producer`'s loop thread
  // records into its ring (0 .. producers - 1).
  void record(std::size_t producer, const CycleTime& cycle, std::uint16_t device, const DeviceState& state,
              const JointCommand& command) noexcept;
  [[nodiscard]] std::size_t producers() const noexcept { return rings_.size(); }
  // Not real-time safe. Writes what is queued, stops the writer and closes the file.
  void finish();

  [[nodiscard]] std::uint64_t written() const noexcept { return written_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t dropped() const noexcept { return dropped_.load(std::memory_order_relaxed); }
  // A write, sync or close failed: the records not in the file (the failed chunk and all after it).
  [[nodiscard]] bool failed() const noexcept { return failed_.load(std::memory_order_acquire); }
  [[nodiscard]] std::uint64_t lost() const noexcept { return lost_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::string error() const;
  [[nodiscard]] const std::filesystem::path& file() const noexcept { return file_; }

 private:
  void write_loop();
  void format_record(const CycleRecord& r);
  // Writes the chunk (whole records); false on failure (then the recorder has failed).
  bool flush_chunk();
  bool sync_file();
  void fail(const std::string& what, int error_number, std::uint64_t records_lost);

  std::vector<std::string> device_names_;
  bool wait_when_full_;
  std::vector<std::unique_ptr<SpscRing<CycleRecord>>> rings_;  // one per producer
  std::filesystem::path file_;
  int fd_ = -1;
  std::string chunk_;  // formatted whole records not yet written (writer thread)
  std::uint64_t chunk_records_ = 0;
  std::int64_t written_bytes_ = 0;  // file offset after the last whole record written
  std::int64_t synced_bytes_ = 0;   // ... and synced to the disk
  std::uint64_t synced_records_ = 0;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> written_{0};
  std::atomic<std::uint64_t> dropped_{0};
  std::atomic<std::uint64_t> lost_{0};
  std::atomic<bool> failed_{false};
  mutable std::mutex error_mutex_;  // error_ (writer thread -> any thread; never the loop)
  std::string error_;
  std::thread writer_;
};

}  // namespace hapticd::server
