#include "playback_device.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <utility>

#include "hapticd/recording/recording_reader.hpp"

namespace hapticd::playback {
namespace {

constexpr const char* kPosition = "joints/position";
constexpr const char* kVelocity = "joints/velocity";
constexpr const char* kEffort = "joints/torque_measured";
constexpr const char* kWrench = "wrench/sensor";
constexpr const char* kTime = "time_s";

std::filesystem::path resolved(const std::string& file, const std::filesystem::path& folder) {
  const std::filesystem::path p(file);
  return p.is_absolute() ? p : folder / p;
}

}  // namespace

ParameterSchema PlaybackDevice::parameter_schema() {
  ParameterSchema s;
  s.string("recording", "the recording to replay (hapticd --record; relative paths: from the session file's folder)");
  s.string("device", "the recorded device to replay; empty: the recording's only device").default_value(std::string());
  s.string("urdf",
           "robot model of the device; empty: the one the recording names (its robot_model_file, relative paths "
           "from the session file's folder)")
      .default_value(std::string());
  s.real("speed", "playback speed: recording seconds per loop second")
      .greater_than(0.0)
      .maximum(100.0)
      .default_value(1.0);
  s.real("start_s", "start this far into the recording").unit("s").minimum(0.0).default_value(0.0);
  s.string("at_end",
           "after the last recorded cycle: hold (the last sample, for ever), loop (from the start again) or fault "
           "(the device goes to its safe mode: 'the recording ended')")
      .choices({"hold", "loop", "fault"})
      .default_value(std::string("hold"));
  s.boolean("wrench", "replay the force/torque sensor's readings (when the recorded device had a sensor)")
      .default_value(true);
  return s;
}

void PlaybackDevice::configure(const Parameters& p, const PluginContext& context) {
  const std::filesystem::path file = resolved(p.string("recording"), context.config_directory);
  // An unreadable file is the recording's fault; a device it lacks, the device parameter's.
  std::vector<std::string> devices;
  try {
    devices = recording::recorded_devices(file);
  } catch (const std::exception& e) {
    throw ParameterError("recording", e.what());
  }
  std::string names;
  for (const std::string& d : devices) names += (names.empty() ? "" : ", ") + d;
  std::string device = p.string("device");
  if (device.empty()) {
    if (devices.size() != 1)
      throw ParameterError("device", file.string() + " has " + std::to_string(devices.size()) + " devices (" + names +
                                         "): name the one to replay");
    device = devices.front();
  } else if (std::find(devices.begin(), devices.end(), device) == devices.end()) {
    throw ParameterError("device", file.string() + " has no device '" + device + "' (it has " + names + ")");
  }
  recording::RecordedDevice r;
  try {
    r = recording::read_device(file, device, {kTime, kPosition, kVelocity, kEffort, kWrench});
  } catch (const std::exception& e) {
    throw ParameterError("recording", e.what());
  }
  if (r.cycles < 2)
    throw ParameterError("recording", file.string() + " holds " + std::to_string(r.cycles) + " cycles of '" + device +
                                          "': nothing to replay");
  // Every dataset as wide as the device it describes (read() indexes them by joint and axis).
  const auto joints = r.description.joints.size();
  for (const auto& [path, width] :
       {std::pair{kTime, std::size_t{1}}, std::pair{kPosition, joints}, std::pair{kVelocity, joints},
        std::pair{kEffort, joints}, std::pair{kWrench, std::size_t{6}}}) {
    const recording::Table& t = r.datasets.at(path);
    if (t.width != width || t.values.size() != t.rows * t.width)
      throw ParameterError("recording", file.string() + ":/devices/" + device + "/" + path + " is " +
                                            std::to_string(t.width) + " wide; the recorded device has " +
                                            std::to_string(joints) + " joints, so it must be " + std::to_string(width));
  }
  if (joints == 0 || joints > static_cast<std::size_t>(kMaxJoints))
    throw ParameterError("recording", file.string() + ": device '" + device + "' has " + std::to_string(joints) +
                                          " joints (1 to " + std::to_string(kMaxJoints) + " can be replayed)");
  description_ = r.description;
  dof_ = description_.dof();
  const std::string urdf = p.string("urdf");
  const std::string model = urdf.empty() ? description_.robot_model_file : urdf;
  if (!model.empty()) {
    const std::filesystem::path path = resolved(model, context.config_directory);
    if (!std::filesystem::exists(path))
      throw ParameterError(urdf.empty() ? "recording" : "urdf",
                           "the robot model " + path.string() + " does not exist" +
                               (urdf.empty() ? " (the recording names it): give it as the parameter urdf" : ""));
    description_.robot_model_file = path.string();
  }
  description_.model = "playback of " + r.description.model;
  description_.simulated = true;               // not hardware
  description_.reports_joint_velocity = true;  // the recorded estimate, so the replay's twist is the recorded one
  description_.reports_joint_torque = false;
  description_.reports_sensor_acceleration = false;
  replay_wrench_ = p.boolean("wrench") && !description_.sensor_frame.empty();
  description_.reports_wrench = replay_wrench_;
  description_.capabilities = {};

  const recording::Table& t = r.datasets.at(kTime);
  times_.resize(r.cycles);
  for (std::size_t k = 0; k < r.cycles; ++k) {
    times_[k] = t.values[k] - t.values[0];
    if (k > 0 && !(times_[k] > times_[k - 1]))
      throw ParameterError(
          "recording", file.string() + ": the times of '" + device + "' do not increase at cycle " + std::to_string(k));
  }
  position_ = std::move(r.datasets.at(kPosition).values);
  velocity_ = std::move(r.datasets.at(kVelocity).values);
  effort_ = std::move(r.datasets.at(kEffort).values);
  wrench_ = std::move(r.datasets.at(kWrench).values);
  speed_ = p.real("speed");
  start_s_ = p.real("start_s");
  if (start_s_ >= duration_s())
    throw ParameterError("start_s", "the recording of '" + device + "' lasts " + std::to_string(duration_s()) + " s");
  const std::string at_end = p.string("at_end");
  at_end_ = at_end == "loop" ? AtEnd::loop : at_end == "fault" ? AtEnd::fault : AtEnd::hold;
}

Outcome PlaybackDevice::enable() {
  first_ns_ = -1;
  return Outcome::success();
}

std::size_t PlaybackDevice::row_at(double t) const noexcept {
  const auto after = std::upper_bound(times_.begin(), times_.end(), t);
  return after == times_.begin() ? 0 : static_cast<std::size_t>(after - times_.begin()) - 1;
}

Outcome PlaybackDevice::read(const CycleTime& cycle, DeviceState& state) {
  if (first_ns_ < 0) first_ns_ = cycle.time_ns;
  double t = start_s_ + speed_ * static_cast<double>(cycle.time_ns - first_ns_) * 1e-9;
  const double length = duration_s();
  if (t > length) {
    if (at_end_ == AtEnd::fault) return Outcome::failure("the recording ended");
    t = at_end_ == AtEnd::loop ? std::fmod(t, length) : length;
  }
  // Linear between the recorded cycles around t (exactly a recorded cycle when the clocks coincide).
  const std::size_t k = row_at(t);
  const std::size_t next = std::min(k + 1, times_.size() - 1);
  const double span = times_[next] - times_[k];
  const double a = span > 0.0 ? std::clamp((t - times_[k]) / span, 0.0, 1.0) : 0.0;
  const auto n = static_cast<std::size_t>(dof_);
  const auto blend = [&](const std::vector<double>& v, std::size_t width, std::size_t i) {
    const double x0 = v[k * width + i], x1 = v[next * width + i];
    return a == 0.0 ? x0 : x0 + a * (x1 - x0);
  };
  state.timestamp_ns = cycle.time_ns;
  for (std::size_t i = 0; i < n; ++i) {
    const auto j = static_cast<Eigen::Index>(i);
    state.joints.position[j] = blend(position_, n, i);
    state.joints.velocity[j] = blend(velocity_, n, i);
    state.joints.effort[j] = blend(effort_, n, i);
  }
  if (replay_wrench_) {
    state.sensor_wrench.force = Eigen::Vector3d(blend(wrench_, 6, 0), blend(wrench_, 6, 1), blend(wrench_, 6, 2));
    state.sensor_wrench.torque = Eigen::Vector3d(blend(wrench_, 6, 3), blend(wrench_, 6, 4), blend(wrench_, 6, 5));
  }
  return Outcome::success();
}

Outcome PlaybackDevice::write(const CycleTime&, const JointCommand& command) {
  if (!command.torque_nm.allFinite()) return Outcome::failure("non-finite torque command");
  return Outcome::success();  // nothing to drive
}

}  // namespace hapticd::playback
