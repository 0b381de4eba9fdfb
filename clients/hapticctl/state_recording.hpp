#pragma once
// hapticctl record: a device's published DDS states written in the server's recording format (HDF5,
// docs/recording.md), so one reader, export and plot serve both. A row per state received (the server may
// publish every Nth cycle: the `cycle` column says which). What the wire does not carry - the measured joint
// torque, the sensor's reading, the engine input in effect, the loop timing - is NaN (reals) or 0 (integers);
// the root attribute `source` says "hapticctl (DDS states)".
#include <chrono>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "hapticd/client/types.hpp"

namespace hapticd::recording {
class RecordingFile;
struct CycleRecord;
}  // namespace hapticd::recording

namespace hapticd::ctl {

class StateRecording {
 public:
  // Creates the file for `device` as its description says. Throws std::runtime_error.
  StateRecording(const std::filesystem::path& file, const client::DeviceInfo& device);
  ~StateRecording();
  StateRecording(const StateRecording&) = delete;
  StateRecording& operator=(const StateRecording&) = delete;

  // Any thread (the client's state callback): keeps the state until the next write().
  void add(const client::DeviceState& state);
  // The caller's thread, now and then: appends the kept states to the file (flushed about every second). Throws.
  void write();
  // Writes what is left and closes the file. Throws.
  void close();
  [[nodiscard]] std::uint64_t states() const noexcept { return written_; }

 private:
  std::vector<std::string> schemes_;  // before file_: its constructor fills them
  std::unique_ptr<recording::RecordingFile> file_;
  std::mutex mutex_;
  std::vector<recording::CycleRecord> pending_;
  std::uint64_t written_ = 0;
  std::chrono::steady_clock::time_point flushed_ = std::chrono::steady_clock::now();
};

}  // namespace hapticd::ctl
