#include "recorder/recorder.hpp"

#include <chrono>
#include <stdexcept>

namespace hapticd::server {

Recorder::Recorder(const std::filesystem::path& file, std::vector<std::string> device_names, bool wait_when_full)
    : device_names_(std::move(device_names)), wait_when_full_(wait_when_full), ring_(1 << 14) {
  out_ = std::fopen(file.c_str(), "w");
  if (out_ == nullptr) throw std::runtime_error("cannot open the recording file " + file.string());
  std::fputs("cycle,time_s,device,joint,position,velocity,effort,torque_command,"
             "sensor_fx,sensor_fy,sensor_fz,sensor_tx,sensor_ty,sensor_tz\n",
             out_);
  writer_ = std::thread([this] { write_loop(); });
}

Recorder::~Recorder() { finish(); }

void Recorder::record(const CycleTime& cycle, std::uint16_t device, const DeviceState& state,
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
  while (!ring_.try_push(r)) {
    if (!wait_when_full_) {
      dropped_.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    std::this_thread::yield();
  }
}

void Recorder::write_record(const CycleRecord& r) {
  const std::string& device = device_names_[r.device];
  for (int i = 0; i < r.dof; ++i)
    std::fprintf(out_, "%llu,%.17g,%s,%d,%.17g,%.17g,%.17g,%.17g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n",
                 static_cast<unsigned long long>(r.cycle), static_cast<double>(r.time_ns) * 1e-9, device.c_str(), i,
                 r.position[i], r.velocity[i], r.effort[i], r.torque_command[i], r.sensor_wrench[0],
                 r.sensor_wrench[1], r.sensor_wrench[2], r.sensor_wrench[3], r.sensor_wrench[4], r.sensor_wrench[5]);
  written_.fetch_add(1, std::memory_order_relaxed);
}

void Recorder::write_loop() {
  CycleRecord r;
  for (;;) {
    bool any = false;
    while (ring_.try_pop(r)) {
      write_record(r);
      any = true;
    }
    if (!any) {
      if (stop_.load(std::memory_order_acquire)) {
        while (ring_.try_pop(r)) write_record(r);
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
  if (out_ != nullptr) {
    std::fclose(out_);
    out_ = nullptr;
  }
}

}  // namespace hapticd::server
