#include "state_recording.hpp"

#include <algorithm>
#include <chrono>
#include <limits>

#include "hapticd/recording/recording_file.hpp"

namespace hapticd::ctl {

using recording::put;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

recording::RecordingHeader header_of(const client::DeviceInfo& d, std::vector<std::string>& schemes) {
  recording::RecordingDevice device;
  device.name = d.device;
  DeviceDescription& desc = device.description;
  desc.model = d.device_plugin;
  desc.simulated = d.simulated;
  desc.handle_frame = d.handle_frame;
  desc.base_pose = d.base_pose;
  for (int j = 0; j < d.dof; ++j)
    desc.joints.push_back({j < static_cast<int>(d.joint_names.size()) ? d.joint_names[static_cast<std::size_t>(j)]
                                                                      : "joint" + std::to_string(j + 1),
                           d.position_min[j], d.position_max[j], d.velocity_max[j], d.torque_peak[j],
                           d.torque_continuous[j]});
  for (const client::SchemeInfo& s : d.schemes) device.schemes.push_back(s.name);
  schemes = device.schemes;
  recording::RecordingHeader h;
  h.source = "hapticctl (DDS states)";
  h.rate_hz = d.rate_hz;
  h.devices.push_back(std::move(device));
  return h;
}

}  // namespace

StateRecording::StateRecording(const std::filesystem::path& file, const client::DeviceInfo& device)
    : file_(std::make_unique<recording::RecordingFile>(file, header_of(device, schemes_))) {}

StateRecording::~StateRecording() = default;

void StateRecording::add(const client::DeviceState& s) {
  recording::CycleRecord r;
  r.cycle = s.cycle;
  r.time_ns = s.loop_time_ns;
  r.device = 0;
  r.dof = static_cast<std::uint8_t>(std::clamp(s.dof, 0, kMaxJoints));
  r.mode = static_cast<std::uint8_t>(s.mode);  // the same order (static_asserts in the bridge and the client)
  r.flags = s.flags;
  const auto scheme = std::find(schemes_.begin(), schemes_.end(), s.scheme.view());
  r.scheme = static_cast<std::uint16_t>(scheme == schemes_.end() ? 0 : scheme - schemes_.begin());
  using recording::put;
  put(r.position, s.position, r.dof);
  put(r.velocity, s.velocity, r.dof);
  put(r.torque_command, s.torque, r.dof);
  std::fill(r.torque_measured, r.torque_measured + r.dof, kNaN);
  put(r.handle_pose, s.pose);
  put(r.handle_twist, s.twist.linear, s.twist.angular);
  r.buttons = s.buttons;
  r.gripper = s.gripper;
  put(r.operator_wrench, s.operator_wrench.force, s.operator_wrench.torque);
  put(r.environment_wrench, s.environment_wrench.force, s.environment_wrench.torque);
  std::fill(std::begin(r.sensor_wrench), std::end(r.sensor_wrench), kNaN);
  put(r.target_pose, s.target_pose);
  r.engine_weight = kNaN;
  r.engine_sequence = s.engine_serial;  // the newest engine command applied
  std::fill(std::begin(r.engine_proxy_pose), std::end(r.engine_proxy_pose), kNaN);
  std::fill(std::begin(r.engine_wrench), std::end(r.engine_wrench), kNaN);
  std::lock_guard lock(mutex_);
  pending_.push_back(r);
}

void StateRecording::write() {
  std::vector<recording::CycleRecord> batch;
  {
    std::lock_guard lock(mutex_);
    batch.swap(pending_);
  }
  if (batch.empty()) return;
  for (const recording::CycleRecord& r : batch) file_->add(r);
  file_->write();
  written_ += batch.size();
  const auto now = std::chrono::steady_clock::now();
  if (now - flushed_ >= std::chrono::seconds(1)) {  // as the server's recorder: a whole file up to here
    file_->flush();
    flushed_ = now;
  }
}

void StateRecording::close() {
  write();
  file_->write_summary("{}", {});
  file_->close();
}

}  // namespace hapticd::ctl
