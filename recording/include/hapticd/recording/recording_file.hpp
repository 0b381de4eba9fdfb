#pragma once
// The recording's HDF5 file (docs/recording.md has the schema): per device one extendible, chunked dataset per
// quantity (rows = cycles), appended in whole records; per session the session file, the device descriptions,
// and at the end the statistics and the safety events. Only this file's .cpp includes hdf5.h. Not real-time:
// the recorder's writer thread uses it. Every HDF5 call is checked: a failure throws std::runtime_error with
// HDF5's own message, and the datasets keep the rows appended before it (their extent is cut back).
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "hapticd/device_description.hpp"
#include "hapticd/recording/cycle_record.hpp"

namespace hapticd::recording {

struct RecordingDevice {
  std::string name;
  DeviceDescription description;
  std::vector<std::string> schemes;  // the control schemes' names, by index (the `scheme` column)
};

struct RecordingHeader {
  std::string source = "hapticd";  // who wrote it: the server, or "hapticctl (DDS states)"
  std::string session_file;        // path as given ("" for a session built from text)
  std::string session_text;        // the session file itself
  double rate_hz = 0.0;
  bool lockstep = false;
  std::vector<RecordingDevice> devices;
};

struct RecordingEvent {
  std::string device;
  std::string kind;  // "fault", "recovery", "recording_failed" (device "": the recording itself)
  std::string code;  // the fault's code (e.g. "SAFETY_VELOCITY")
  std::uint64_t cycle = 0;
  double time_s = 0.0;
};

// One column of the schema: a dataset per device, `width` values per row (0: the device's dof).
struct RecordingColumn {
  const char* path;  // under /devices/<name>/
  const char* type;  // "f64", "i64", "u64", "u32", "u16", "u8"
  int width;
  const char* unit;
  const char* text;
};
// The per-cycle columns in the order of the schema (docs/recording.md lists the same).
const std::vector<RecordingColumn>& recording_columns();

// Why `file` cannot name a recording, or "" if it can: recordings are HDF5, named .h5 or .hdf5 (a run.csv would
// be HDF5 in a file that says CSV; `hapticctl export FILE.h5 --csv` writes CSV from a recording).
std::string recording_name_problem(const std::filesystem::path& file);

inline constexpr const char* kRecordingFormat = "hapticd-recording";
inline constexpr int kRecordingVersion = 1;

class RecordingFile {
 public:
  // Creates the file (truncating one that exists) and writes the header. Throws std::runtime_error.
  RecordingFile(const std::filesystem::path& file, const RecordingHeader& header);
  ~RecordingFile();  // closes (errors ignored: call close() to see them)
  RecordingFile(const RecordingFile&) = delete;
  RecordingFile& operator=(const RecordingFile&) = delete;

  // Buffers a record (its device's columns); write() appends the buffered rows.
  void add(const CycleRecord& r);
  [[nodiscard]] std::size_t buffered() const noexcept;
  // Appends every buffered row to its datasets. On failure throws; the datasets are cut back to the rows
  // before this call and the buffer is dropped (buffered rows are then lost: the caller counts them).
  void write();
  // Writes HDF5's buffers and metadata to the file (a consistent file up to here), then fdatasync.
  void flush();
  // At the end: the session's statistics (JSON, as --stats-json writes it) and its safety events.
  void write_summary(const std::string& statistics_json, const std::vector<RecordingEvent>& events);
  void close();
  [[nodiscard]] std::uint64_t rows(std::size_t device) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hapticd::recording
