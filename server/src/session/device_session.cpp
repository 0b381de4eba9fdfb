#include "session/device_session.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hapticd/model/dynamics.hpp"
#include "hapticd/model/kinematics.hpp"
#include "hapticd/model/urdf_loader.hpp"
#include "session/finite.hpp"

namespace hapticd::server {

std::string_view to_string(DeviceFault fault) noexcept {
  switch (fault) {
    case DeviceFault::none: return "none";
    case DeviceFault::device_read: return "device read failed";
    case DeviceFault::device_write: return "device write failed";
    case DeviceFault::non_finite_measurement: return "device reported a non-finite value";
    case DeviceFault::activation: return "a plugin failed to activate";
    case DeviceFault::virtual_model: return "virtual model update failed";
    case DeviceFault::inverse_kinematics: return "inverse kinematics update failed";
    case DeviceFault::controller: return "controller update failed";
    case DeviceFault::non_finite_output: return "a plugin produced a non-finite output";
    case DeviceFault::emergency_stop: return "emergency stop";
  }
  return "unknown";
}

DeviceSession::DeviceSession(std::string name, DeviceChain chain)
    : name_(std::move(name)), chain_(std::move(chain)), description_(chain_.device->description()) {
  const int dof = description_.dof();
  if (dof < 1 || dof > kMaxJoints)
    throw std::invalid_argument("device '" + name_ + "' reports " + std::to_string(dof) + " joints; supported: 1.." +
                                std::to_string(kMaxJoints));
  torque_limit_nm_.resize(dof);
  for (int i = 0; i < dof; ++i) {
    const double peak = description_.joints[static_cast<std::size_t>(i)].torque_peak_nm;
    if (!(peak > 0.0) || !std::isfinite(peak))
      throw std::invalid_argument("device '" + name_ + "' joint " + std::to_string(i) + " has no valid peak torque");
    torque_limit_nm_[i] = peak;
  }
  if (chain_.schemes.empty()) throw std::invalid_argument("device '" + name_ + "' has no control scheme");
  scheme_state_ = std::vector<std::atomic<std::uint8_t>>(chain_.schemes.size());
  for (auto& st : scheme_state_) st.store(kIdle);
  switch_offset_.setZero(dof);
  state_.joints.resize(dof);
  joint_target_.resize(dof);
  command_.torque_nm.setZero(dof);
  zero_command_.torque_nm.setZero(dof);
  chain_state_.velocity.setZero(dof);
  if (!description_.robot_model_file.empty()) {
    robot_ = std::make_unique<model::RobotModel>(model::load_robot_model(description_.robot_model_file));
    if (robot_->dof() != dof) {
      throw std::invalid_argument("device '" + name_ + "': its robot model " + description_.robot_model_file + " has " +
                                  std::to_string(robot_->dof()) + " joints, the device " + std::to_string(dof));
    }
    model_data_ = std::make_unique<model::ModelData>(*robot_);
    chain_state_.model = robot_.get();
    chain_state_.data = model_data_.get();
    chain_state_.handle_frame = robot_->require_frame(description_.handle_frame.empty() ? "handle" : description_.handle_frame);
    if (description_.reports_wrench && !description_.sensor_frame.empty()) {
      sensor_frame_ = robot_->require_frame(description_.sensor_frame);
    }
  }
}

void DeviceSession::activate() {
  chain_.device->activate();
  chain_active_ = false;
  command_.torque_nm.setZero();
  switch_ramp_left_ = 0;
}

ReturnCode DeviceSession::activate_scheme(SchemeChain& scheme) noexcept {
  if (scheme.virtual_model &&
      (*scheme.virtual_model)->activate(VirtualModelInput{state_, &chain_state_, &engine_}) != ReturnCode::ok)
    return ReturnCode::error;
  if (scheme.inverse_kinematics &&
      (*scheme.inverse_kinematics)->activate(InverseKinematicsInput{state_, task_, &chain_state_}) != ReturnCode::ok)
    return ReturnCode::error;
  return scheme.controller->activate(ControllerInput{state_, task_, joint_target_, &chain_state_}, command_);
}

bool DeviceSession::request_scheme(std::string_view name) {
  for (std::size_t i = 0; i < chain_.schemes.size(); ++i) {
    if (chain_.schemes[i].name == name) {
      requested_.store(static_cast<int>(i), std::memory_order_release);
      return true;
    }
  }
  return false;
}

const std::string& DeviceSession::active_scheme() const noexcept {
  return chain_.schemes[static_cast<std::size_t>(active_.load(std::memory_order_acquire))].name;
}

void DeviceSession::service() {
  for (std::size_t i = 0; i < chain_.schemes.size(); ++i) {
    if (scheme_state_[i].load(std::memory_order_acquire) != kLeaving) continue;
    SchemeChain& s = chain_.schemes[i];
    s.controller->deactivate();
    if (s.inverse_kinematics) (*s.inverse_kinematics)->deactivate();
    if (s.virtual_model) (*s.virtual_model)->deactivate();
    scheme_state_[i].store(kIdle, std::memory_order_release);
  }
}

RuntimeReply DeviceSession::handle_request(std::string_view stage, std::string_view name, const std::vector<double>& values) {
  if (stage == "device") return chain_.device->handle_request(name, values);
  SchemeChain& scheme = chain_.schemes[static_cast<std::size_t>(active_.load(std::memory_order_acquire))];
  if (stage == "controller") return scheme.controller->handle_request(name, values);
  if (stage == "virtual_model") {
    if (!scheme.virtual_model) return {false, "scheme '" + scheme.name + "' has no virtual model"};
    return (*scheme.virtual_model)->handle_request(name, values);
  }
  return {false, "unknown stage '" + std::string(stage) + "' (device, virtual_model or controller)"};
}

void DeviceSession::switch_scheme_if_requested(const CycleTime& cycle) noexcept {
  const int wanted = requested_.load(std::memory_order_acquire);
  const int current = active_.load(std::memory_order_relaxed);
  if (wanted == current) return;
  const auto w = static_cast<std::size_t>(wanted);
  if (scheme_state_[w].load(std::memory_order_acquire) != kIdle) return;  // still leaving: wait for service()
  const JointVector before = command_.torque_nm;
  if (activate_scheme(chain_.schemes[w]) != ReturnCode::ok) {
    refused_switches_.fetch_add(1, std::memory_order_relaxed);
    requested_.store(current, std::memory_order_release);  // keep running the old scheme
    // Parts of the chain may have activated before one refused: service() deactivates them off the loop.
    scheme_state_[w].store(kLeaving, std::memory_order_release);
    return;
  }
  scheme_state_[static_cast<std::size_t>(current)].store(kLeaving, std::memory_order_release);
  scheme_state_[w].store(kActive, std::memory_order_release);
  active_.store(wanted, std::memory_order_release);
  switches_.fetch_add(1, std::memory_order_relaxed);
  // The offset is measured against the new scheme's first command in run_chain.
  switch_offset_ = before;
  switch_ramp_cycles_ = std::max<std::int64_t>(
      1, static_cast<std::int64_t>(std::llround(chain_.switch_ramp_s * 1e9 / static_cast<double>(cycle.period_ns))));
  switch_ramp_left_ = -1;  // marks "offset not yet taken"
}

void DeviceSession::update_chain_state(bool first_cycle) noexcept {
  ChainState& c = chain_state_;
  if (description_.reports_joint_velocity) {
    c.velocity = state_.joints.velocity;
  } else if (first_cycle) {
    differentiator_.reset(state_.joints.position);
    c.velocity.setZero();
  } else {
    c.velocity = differentiator_.update(state_.joints.position);
  }
  if (robot_ == nullptr) return;
  model::compute_cycle_terms(*robot_, *model_data_, state_.joints.position, c.velocity, c.handle_frame);
  const model::ModelData& d = *model_data_;
  c.handle_pose.position = d.frame_pose.translation();
  c.handle_pose.orientation = Eigen::Quaterniond(d.frame_pose.linear());
  const model::Vector6d twist = d.frame_jacobian * c.velocity;
  c.handle_twist.linear = twist.head<3>();
  c.handle_twist.angular = twist.tail<3>();
  if (sensor_frame_ >= 0) {
    // The sensor's wrench, turned into the world and moved to the handle point (the handle's own dynamics
    // beyond the sensor are not subtracted yet).
    const Eigen::Isometry3d sensor = model::frame_pose(*robot_, d, sensor_frame_);
    const Eigen::Vector3d force = sensor.linear() * state_.sensor_wrench.force;
    const Eigen::Vector3d moment = sensor.linear() * state_.sensor_wrench.torque;
    c.operator_wrench.force = force;
    c.operator_wrench.torque = moment + (sensor.translation() - c.handle_pose.position).cross(force);
    c.has_operator_wrench = true;
  }
}

DeviceFault DeviceSession::run_chain(const CycleTime& cycle) noexcept {
  if (!chain_active_) {
    differentiator_.configure(static_cast<double>(cycle.period_ns) * 1e-9, kVelocityFilterHz);
    update_chain_state(true);
    const int first = active_.load(std::memory_order_relaxed);
    if (activate_scheme(chain_.schemes[static_cast<std::size_t>(first)]) != ReturnCode::ok) return DeviceFault::activation;
    scheme_state_[static_cast<std::size_t>(first)].store(kActive, std::memory_order_release);
    chain_active_ = true;
  } else {
    update_chain_state(false);
    switch_scheme_if_requested(cycle);
  }
  take_engine_input(cycle);
  SchemeChain& scheme = chain_.schemes[static_cast<std::size_t>(active_.load(std::memory_order_relaxed))];
  if (scheme.virtual_model) {
    if ((*scheme.virtual_model)->update(cycle, VirtualModelInput{state_, &chain_state_, &engine_}, task_) != ReturnCode::ok)
      return DeviceFault::virtual_model;
    if (!is_finite(task_)) return DeviceFault::non_finite_output;
  } else {
    task_ = TaskTarget{};  // a scheme without a virtual model renders nothing (free space)
  }
  if (scheme.inverse_kinematics) {
    if ((*scheme.inverse_kinematics)->update(cycle, InverseKinematicsInput{state_, task_, &chain_state_}, joint_target_) != ReturnCode::ok)
      return DeviceFault::inverse_kinematics;
    if (!is_finite(joint_target_)) return DeviceFault::non_finite_output;
  }
  if (scheme.controller->update(cycle, ControllerInput{state_, task_, joint_target_, &chain_state_}, command_) != ReturnCode::ok)
    return DeviceFault::controller;
  if (!command_.torque_nm.allFinite()) return DeviceFault::non_finite_output;
  blend_after_switch();
  return DeviceFault::none;
}

void DeviceSession::take_engine_input(const CycleTime& cycle) noexcept {
  if (engine_inbox_.take(engine_incoming_)) {
    engine_ = engine_incoming_;
    engine_.received_ns = cycle.time_ns;
    engine_seen_ = true;
  }
  if (!engine_seen_) {
    engine_.weight = engine_weight_ = 0.0;
    return;
  }
  // Fresh until the deadline, then a linear fade to zero (the safety deadline of docs/dds-interface.md). Input
  // that (re)starts after a silence is ramped in over engine_ramp_in_s (soft start: no force step when an
  // engine connects or reconnects).
  const double age = static_cast<double>(cycle.time_ns - engine_.received_ns) * 1e-9;
  const double late = age - chain_.engine_deadline_s;
  const double target = late <= 0.0 ? 1.0 : std::clamp(1.0 - late / std::max(chain_.engine_fade_s, 1e-9), 0.0, 1.0);
  const double step = static_cast<double>(cycle.period_ns) * 1e-9 / std::max(chain_.engine_ramp_in_s, 1e-9);
  engine_.weight = target > engine_weight_ ? std::min(target, engine_weight_ + step) : target;
  engine_weight_ = engine_.weight;
  engine_late_ = late > 0.0;
}

void DeviceSession::publish_snapshot(const CycleTime& cycle, double torque_scale) noexcept {
  if (snapshot_interval_ == 0 || cycle.index % snapshot_interval_ != 0) return;
  DeviceSnapshot& s = snapshot_;
  s.cycle = cycle.index;
  s.time_ns = cycle.time_ns;
  s.handle_pose = chain_state_.handle_pose;
  s.handle_twist = chain_state_.handle_twist;
  s.operator_wrench = chain_state_.operator_wrench;
  s.environment_wrench = task_.wrench;
  s.target_pose = task_.pose;
  s.position = state_.joints.position;
  s.velocity = chain_state_.velocity;
  s.torque = command_.torque_nm;
  s.fault = fault();
  s.estop = s.fault == DeviceFault::emergency_stop;
  s.stopping = torque_scale < 1.0;
  s.saturated = chain_state_.output_saturated;
  s.switching = switch_ramp_left_ != 0;
  s.scheme = active_.load(std::memory_order_relaxed);
  s.engine_weight = engine_.weight;
  s.engine_stale = engine_seen_ && engine_late_;
  s.engine_sequence = engine_.sequence;
  snapshot_outbox_.publish(s);
}

void DeviceSession::blend_after_switch() noexcept {
  if (switch_ramp_left_ == 0) return;
  if (switch_ramp_left_ < 0) {  // the new scheme's first command: take the difference to the old one
    switch_offset_ -= command_.torque_nm;
    switch_ramp_left_ = switch_ramp_cycles_;
  }
  command_.torque_nm += switch_offset_ * (static_cast<double>(switch_ramp_left_) / static_cast<double>(switch_ramp_cycles_));
  --switch_ramp_left_;
}

void DeviceSession::cycle(const CycleTime& cycle, double torque_scale) noexcept {
  cycle_checked(cycle, torque_scale);
  publish_snapshot(cycle, torque_scale);
}

void DeviceSession::cycle_checked(const CycleTime& cycle, double torque_scale) noexcept {
  const ReturnCode read = chain_.device->read(cycle, state_);
  if (fault() == DeviceFault::none && estop_requested_.load(std::memory_order_acquire))
    enter_safe_state(DeviceFault::emergency_stop, cycle);
  if (fault() != DeviceFault::none) {
    write_zero_torque(cycle);
    return;
  }
  if (read != ReturnCode::ok) return enter_safe_state(DeviceFault::device_read, cycle);
  if (!is_finite(state_)) return enter_safe_state(DeviceFault::non_finite_measurement, cycle);

  if (const DeviceFault f = run_chain(cycle); f != DeviceFault::none) return enter_safe_state(f, cycle);

  const auto limited = command_.torque_nm.cwiseMax(-torque_limit_nm_).cwiseMin(torque_limit_nm_);
  chain_state_.output_saturated = (limited.array() != command_.torque_nm.array()).any();
  if (chain_state_.output_saturated) saturated_cycles_.fetch_add(1, std::memory_order_relaxed);
  const double scale = std::clamp(torque_scale, 0.0, 1.0);
  if (scale > 0.0) {
    command_.torque_nm = limited * scale;
  } else {
    command_.torque_nm.setZero();  // exactly +0, not -0 from a negative torque times zero
  }

  if (chain_.device->write(cycle, command_) != ReturnCode::ok) enter_safe_state(DeviceFault::device_write, cycle);
}

void DeviceSession::write_zero_torque(const CycleTime& cycle) noexcept {
  command_.torque_nm.setZero();
  (void)chain_.device->write(cycle, zero_command_);
}

void DeviceSession::enter_safe_state(DeviceFault fault, const CycleTime& cycle) noexcept {
  fault_cycle_.store(cycle.index, std::memory_order_relaxed);
  fault_.store(fault, std::memory_order_release);
  write_zero_torque(cycle);
}

void DeviceSession::deactivate() {
  for (auto& st : scheme_state_) {
    if (st.load(std::memory_order_acquire) == kActive) st.store(kLeaving, std::memory_order_release);
  }
  chain_active_ = false;
  service();
  chain_.device->deactivate();
}

}  // namespace hapticd::server
