#include "recorder/recorder.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "recorder/fill_record.hpp"

namespace hapticd::server {
namespace {

constexpr std::size_t kWriteRecords = 2048;  // appended when this many are buffered (or when the rings are empty)
constexpr auto kFlushInterval = std::chrono::seconds(1);

}  // namespace

Recorder::Recorder(const std::filesystem::path& file, const RecordingHeader& header, bool wait_when_full,
                   std::size_t producers)
    : wait_when_full_(wait_when_full), path_(file) {
  for (std::size_t k = 0; k < std::max<std::size_t>(1, producers); ++k)
    rings_.push_back(std::make_unique<realtime::SpscRing<CycleRecord>>(1 << 13));
  scratch_.resize(rings_.size());
  file_ = std::make_unique<RecordingFile>(file, header);  // throws with the reason
  last_flush_ = std::chrono::steady_clock::now();
  writer_ = std::thread([this] { write_loop(); });
}

Recorder::~Recorder() {
  finish();
  if (file_) close();
}

void Recorder::record(std::size_t producer, const CycleRecord& r) noexcept {
  realtime::SpscRing<CycleRecord>& ring = *rings_[producer];
  while (!ring.try_push(r)) {
    if (!wait_when_full_) {
      dropped_.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    std::this_thread::yield();
  }
}

void Recorder::device_written(std::size_t producer, const DeviceSession& device, std::uint16_t index,
                              const CycleTime& cycle, std::int64_t lateness_ns, std::int64_t compute_ns) noexcept {
  CycleRecord& r = scratch_[producer];
  fill_cycle_record(r, device, index, cycle, lateness_ns, compute_ns);
  record(producer, r);
}

std::string Recorder::error() const {
  std::lock_guard lock(error_mutex_);
  return error_;
}

void Recorder::fail(const std::string& message, std::uint64_t records_lost) {
  {
    std::lock_guard lock(error_mutex_);
    if (error_.empty()) error_ = message;
  }
  lost_.fetch_add(records_lost, std::memory_order_relaxed);
  failed_.store(true, std::memory_order_release);
}

void Recorder::take(const CycleRecord& r) {
  if (failed()) {
    lost_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  file_->add(r);
  if (file_->buffered() >= kWriteRecords) write_buffered();
}

void Recorder::write_buffered() {
  if (failed() || file_->buffered() == 0) return;
  const std::size_t n = file_->buffered();
  try {
    file_->write();
  } catch (const std::exception& e) {
    fail(e.what(), n);
    return;
  }
  written_.fetch_add(n, std::memory_order_relaxed);
  unflushed_ += n;
  if (std::chrono::steady_clock::now() - last_flush_ >= kFlushInterval) flush_file();
}

void Recorder::flush_file() {
  if (failed()) return;
  try {
    file_->flush();
  } catch (const std::exception& e) {
    // What was written since the last flush may not be in the file: count it as lost.
    written_.fetch_sub(unflushed_, std::memory_order_relaxed);
    fail(e.what(), unflushed_);
  }
  unflushed_ = 0;
  last_flush_ = std::chrono::steady_clock::now();
}

void Recorder::write_loop() {
  CycleRecord r;
  for (;;) {
    bool any = false;
    for (const auto& ring : rings_) {
      while (ring->try_pop(r)) {
        take(r);
        any = true;
      }
    }
    write_buffered();
    if (!any) {
      if (stop_.load(std::memory_order_acquire)) {
        for (const auto& ring : rings_)
          while (ring->try_pop(r)) take(r);
        write_buffered();
        flush_file();
        return;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  }
}

void Recorder::finish() {
  if (writer_.joinable()) {
    stop_.store(true, std::memory_order_release);
    writer_.join();
  }
}

void Recorder::close(const std::string& statistics_json, const std::vector<RecordingEvent>& events) {
  finish();
  if (!file_) return;
  try {
    // After a failure the summary is still written when the file is whole (the recording stopped before the
    // disk was full); after a failed write it fails again, and the close says so.
    file_->write_summary(statistics_json, events);
    file_->close();
  } catch (const std::exception& e) {
    fail(e.what(), 0);
  }
  file_.reset();
}

}  // namespace hapticd::server
