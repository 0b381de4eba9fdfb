#pragma once
// Records every cycle of every device to an HDF5 file (recording_file.hpp; docs/recording.md) without touching
// the loop's timing: the loop pushes fixed-size CycleRecords into a lock-free ring (one per loop thread), a
// writer thread appends them to the file in chunks of whole records. In real-time mode a full ring drops the
// record (counted); in lockstep mode the loop waits for the writer instead, so a recording is complete.
// Every write is checked. A failing write (a full disk, an I/O error) leaves the datasets at the records before
// it; the recorder stops writing and counts every record from then on as lost (failed(), error(), lost()).
// The file is flushed (HDF5's metadata and data, then fdatasync) about every second and at the end: what was
// flushed stays readable whatever happens later; a failing flush counts the records since the last one as lost.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "cycle/device_cycle_sink.hpp"
#include "hapticd/realtime/spsc_ring.hpp"
#include "hapticd/recording/cycle_record.hpp"
#include "hapticd/recording/recording_file.hpp"

namespace hapticd::server {

// The recording library's types, as the recorder speaks them.
using recording::CycleRecord;
using recording::RecordingDevice;
using recording::RecordingEvent;
using recording::RecordingFile;
using recording::RecordingHeader;

class Recorder final : public DeviceCycleSink {
 public:
  // Creates the file and writes the header (throws std::runtime_error if it cannot), starts the writer thread.
  // producers: the loop threads that record, each into a ring of its own.
  Recorder(const std::filesystem::path& file, const RecordingHeader& header, bool wait_when_full,
           std::size_t producers = 1);
  ~Recorder() override;
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  // Real-time safe (in real-time mode; in lockstep it may wait for the writer). Only `producer`'s loop thread
  // records into its ring (0 .. producers - 1).
  void record(std::size_t producer, const CycleRecord& record) noexcept;
  [[nodiscard]] std::size_t producers() const noexcept override { return rings_.size(); }
  // The loop's hand-over (DeviceCycleSink): the device's record of the cycle, into `producer`'s ring.
  void device_written(std::size_t producer, const DeviceSession& device, std::uint16_t index, const CycleTime& cycle,
                      std::int64_t lateness_ns, std::int64_t compute_ns) noexcept override;
  // Not real-time safe. Writes what is queued and stops the writer; the file stays open for the summary.
  void finish();
  // After finish(): the session's statistics and safety events, then closes the file. A failure here fails the
  // recording (the cycles already flushed stay readable).
  void close(const std::string& statistics_json = "{}", const std::vector<RecordingEvent>& events = {});

  [[nodiscard]] std::uint64_t written() const noexcept { return written_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t dropped() const noexcept { return dropped_.load(std::memory_order_relaxed); }
  [[nodiscard]] bool failed() const noexcept { return failed_.load(std::memory_order_acquire); }
  [[nodiscard]] std::uint64_t lost() const noexcept { return lost_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::string error() const;
  [[nodiscard]] const std::filesystem::path& file() const noexcept { return path_; }

 private:
  void write_loop();
  void take(const CycleRecord& r);
  void write_buffered();
  void flush_file();
  void fail(const std::string& message, std::uint64_t records_lost);

  bool wait_when_full_;
  std::vector<std::unique_ptr<realtime::SpscRing<CycleRecord>>> rings_;  // one per producer
  std::vector<CycleRecord> scratch_;  // one per producer: a record is 1.6 kB, not for the loop's stack
  std::filesystem::path path_;
  std::unique_ptr<RecordingFile> file_;  // writer thread (then the caller of finish/close)
  std::uint64_t unflushed_ = 0;          // records written since the last flush
  std::chrono::steady_clock::time_point last_flush_;
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
