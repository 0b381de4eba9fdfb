#include "recorder/recorder.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace hapticd::server {
namespace {

constexpr std::size_t kChunkBytes = 64 * 1024;        // written when this full (or when the ring is empty)
constexpr std::int64_t kSyncBytes = 4 * 1024 * 1024;  // synced to the disk this often

}  // namespace

Recorder::Recorder(const std::filesystem::path& file, std::vector<std::string> device_names, bool wait_when_full,
                   std::size_t producers)
    : device_names_(std::move(device_names)), wait_when_full_(wait_when_full), file_(file) {
  for (std::size_t k = 0; k < std::max<std::size_t>(1, producers); ++k)
    rings_.push_back(std::make_unique<SpscRing<CycleRecord>>(1 << 14));
  fd_ = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0)
    throw std::runtime_error("cannot open the recording file " + file.string() + ": " + std::strerror(errno));
  chunk_.reserve(2 * kChunkBytes);
  chunk_ =
      "cycle,time_s,device,joint,position,velocity,effort,torque_command,"
      "sensor_fx,sensor_fy,sensor_fz,sensor_tx,sensor_ty,sensor_tz\n";
  if (!flush_chunk()) {
    const std::string e = error();
    ::close(fd_);
    fd_ = -1;
    throw std::runtime_error(e);
  }
  writer_ = std::thread([this] { write_loop(); });
}

Recorder::~Recorder() { finish(); }

void Recorder::record(std::size_t producer, const CycleTime& cycle, std::uint16_t device, const DeviceState& state,
                      const JointCommand& command) noexcept {
  CycleRecord r;
  r.cycle = cycle.index;
  r.time_ns = cycle.time_ns;
  r.device = device;
  r.dof = static_cast<std::uint8_t>(state.joints.position.size());
  for (int i = 0; i < r.dof; ++i) {
    r.position[i] = state.joints.position[i];
    r.velocity[i] = state.joints.velocity[i];
    r.effort[i] = state.joints.effort[i];
    r.torque_command[i] = command.torque_nm[i];
  }
  for (int a = 0; a < 3; ++a) {
    r.sensor_wrench[a] = state.sensor_wrench.force[a];
    r.sensor_wrench[3 + a] = state.sensor_wrench.torque[a];
  }
  SpscRing<CycleRecord>& ring = *rings_[producer];
  while (!ring.try_push(r)) {
    if (!wait_when_full_) {
      dropped_.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    std::this_thread::yield();
  }
}

std::string Recorder::error() const {
  std::lock_guard lock(error_mutex_);
  return error_;
}

void Recorder::fail(const std::string& what, int error_number, std::uint64_t records_lost) {
  {
    std::lock_guard lock(error_mutex_);
    error_ = what + " " + file_.string() + ": " + std::strerror(error_number);
  }
  lost_.fetch_add(records_lost, std::memory_order_relaxed);
  failed_.store(true, std::memory_order_release);
}

void Recorder::format_record(const CycleRecord& r) {
  const std::string& device = device_names_[r.device];
  char line[512];
  for (int i = 0; i < r.dof; ++i) {
    const int n = std::snprintf(
        line, sizeof line, "%llu,%.17g,%s,%d,%.17g,%.17g,%.17g,%.17g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n",
        static_cast<unsigned long long>(r.cycle), static_cast<double>(r.time_ns) * 1e-9, device.c_str(), i,
        r.position[i], r.velocity[i], r.effort[i], r.torque_command[i], r.sensor_wrench[0], r.sensor_wrench[1],
        r.sensor_wrench[2], r.sensor_wrench[3], r.sensor_wrench[4], r.sensor_wrench[5]);
    chunk_.append(line, static_cast<std::size_t>(std::clamp(n, 0, static_cast<int>(sizeof line) - 1)));
  }
  ++chunk_records_;
}

bool Recorder::flush_chunk() {
  if (failed()) {
    lost_.fetch_add(chunk_records_, std::memory_order_relaxed);
  } else {
    std::size_t done = 0;
    while (done < chunk_.size()) {
      const ssize_t n = ::write(fd_, chunk_.data() + done, chunk_.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        const int e = n < 0 ? errno : ENOSPC;
        // Cut a partly written chunk back to the last whole record (not possible on a device such as /dev/full).
        if (done > 0) (void)::ftruncate(fd_, written_bytes_);
        fail("cannot write the recording", e, chunk_records_);
        break;
      }
      done += static_cast<std::size_t>(n);
    }
    if (!failed()) {
      written_bytes_ += static_cast<std::int64_t>(chunk_.size());
      written_.fetch_add(chunk_records_, std::memory_order_relaxed);
    }
  }
  chunk_.clear();
  chunk_records_ = 0;
  if (!failed() && written_bytes_ - synced_bytes_ >= kSyncBytes) (void)sync_file();
  return !failed();
}

bool Recorder::sync_file() {
  if (::fdatasync(fd_) == 0 || errno == EINVAL || errno == EROFS) {  // EINVAL: a file that cannot be synced
    synced_bytes_ = written_bytes_;
    synced_records_ = written_.load(std::memory_order_relaxed);
    return true;
  }
  // What was written since the last sync may not be on the disk: keep only what is known to be there.
  const int e = errno;
  (void)::ftruncate(fd_, synced_bytes_);
  const std::uint64_t unsynced = written_.load(std::memory_order_relaxed) - synced_records_;
  written_.fetch_sub(unsynced, std::memory_order_relaxed);
  fail("cannot sync the recording", e, unsynced);
  return false;
}

void Recorder::write_loop() {
  CycleRecord r;
  for (;;) {
    bool any = false;
    for (const auto& ring : rings_) {
      while (ring->try_pop(r)) {
        format_record(r);
        any = true;
        if (chunk_.size() >= kChunkBytes) (void)flush_chunk();
      }
    }
    if (!chunk_.empty()) (void)flush_chunk();
    if (!any) {
      if (stop_.load(std::memory_order_acquire)) {
        for (const auto& ring : rings_)
          while (ring->try_pop(r)) format_record(r);
        (void)flush_chunk();
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
  if (fd_ >= 0) {
    if (!failed()) (void)sync_file();
    if (::close(fd_) != 0 && !failed()) fail("cannot close the recording", errno, 0);
    fd_ = -1;
  }
}

}  // namespace hapticd::server
