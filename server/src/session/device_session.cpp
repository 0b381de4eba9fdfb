#include "session/device_session.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <thread>
#include <type_traits>

#include "executor/loop_clock.hpp"
#include "hapticd/demand.hpp"
#include "session/finite.hpp"

namespace hapticd::server {
namespace {

// The scheme's redundancy resolution for its controller (nullptr without an IK or when it offers none).
RedundancyResolution* redundancy_of(SchemeChain& scheme) noexcept {
  return scheme.inverse_kinematics ? (*scheme.inverse_kinematics)->redundancy() : nullptr;
}

// A device's reason as the status keeps it: nullptr when it gave none.
const char* reason_or_null(const char* reason) noexcept {
  return reason != nullptr && reason[0] != '\0' ? reason : nullptr;
}

}  // namespace

const DeviceDescription& DeviceSession::checked(const std::string& name, const DeviceChain& chain) {
  const DeviceDescription& description = chain.description;
  const int dof = description.dof();
  if (dof < 1 || dof > kMaxJoints)
    throw std::invalid_argument("device '" + name + "' reports " + std::to_string(dof) + " joints; supported: 1.." +
                                std::to_string(kMaxJoints));
  for (int i = 0; i < dof; ++i) {
    const double peak = description.joints[static_cast<std::size_t>(i)].torque_peak_nm;
    if (!(peak > 0.0) || !std::isfinite(peak))
      throw std::invalid_argument("device '" + name + "' joint " + std::to_string(i) + " has no valid peak torque");
  }
  if (chain.schemes.empty() && chain.configure_error.empty())
    throw std::invalid_argument("device '" + name + "' has no control scheme");
  if (!(chain.period_s > 0.0)) throw std::invalid_argument("device '" + name + "': no loop period");
  return description;
}

DeviceSession::DeviceSession(std::string name, DeviceChain chain)
    : name_(std::move(name)),
      chain_(std::move(chain)),
      description_(checked(name_, chain_)),
      estimator_(description_, chain_.robot_model, chain_.period_s),
      engine_(EngineTiming{chain_.engine_deadline_s, chain_.engine_fade_s, chain_.engine_ramp_in_s}),
      schemes_(chain_.schemes),
      requests_(name_, chain_, status_, schemes_, engine_),
      blend_(std::llround(chain_.switch_ramp_s / chain_.period_s)) {
  const int dof = description_.dof();
  state_.joints.resize(dof);
  if (!chain_.configure_error.empty()) {
    status_.fault_.store(DeviceFault::configure);
    status_.faults_.store(1);
  }
  joint_target_.resize(dof);
  command_.torque_nm.setZero(dof);
  last_written_.setZero(dof);
  // Everything sized and set up for the loop's period here, before the first cycle: nothing lazily on the loop.
  safety_.configure(chain_.safety, description_, chain_.period_s);
  status_.passivity_control_.store(safety_.guard().passivity_control(), std::memory_order_release);
}

void DeviceSession::activate() noexcept {
  // The device's lifecycle up to its first read: enable (drives on, brakes released), then homing if it needs
  // it. A step that fails holds the device in its safe state with the reason; the other devices run.
  const auto step = [](auto&& call) {
    try {
      return call();
    } catch (...) {
      return Outcome::failure("threw an exception");
    }
  };
  Outcome enabled = step([&] { return chain_.device->enable(); });
  if (!enabled.ok()) {
    hold_before_start(DeviceFault::device_enable, enabled.reason);
  } else if (description_.capabilities.homing) {
    const Outcome homed = step([&] { return chain_.device->home(); });
    if (!homed.ok()) hold_before_start(DeviceFault::device_homing, homed.reason);
  }
  chain_active_ = false;
  estimator_.reset();
  command_.torque_nm.setZero();
  blend_.cancel();
}

Outcome DeviceSession::activate_scheme(SchemeChain& scheme) noexcept {
  // Real-time methods must not throw; one that does anyway is refused like one that reports an error.
  try {
    if (scheme.virtual_model) {
      const Outcome o = (*scheme.virtual_model)
                            ->activate(VirtualModelInput{state_, estimator_.state(), engine_.input(), safety_.guard()});
      if (!o.ok()) return o;
    }
    if (scheme.inverse_kinematics) {
      const Outcome o =
          (*scheme.inverse_kinematics)->activate(InverseKinematicsInput{state_, task_, estimator_.state()});
      if (!o.ok()) return o;
    }
    return scheme.controller->activate(
        ControllerInput{state_, task_, joint_target_, estimator_.state(), redundancy_of(scheme)}, command_);
  } catch (...) {
    return Outcome::failure("a plugin threw an exception in activate()");
  }
}

void DeviceSession::service() {
  // A request never reaches a plugin while it is deactivated; while one is served, the next round does it.
  std::unique_lock lock(requests_.plugin_requests_, std::try_to_lock);
  if (lock.owns_lock()) schemes_.service();
}

void DeviceSession::switch_scheme_if_requested() noexcept {
  SchemeChain* wanted = schemes_.wanted();
  if (wanted == nullptr) return;
  const JointVector before = command_.torque_nm;
  if (!activate_scheme(*wanted).ok()) {
    schemes_.refused_switch();  // the old scheme runs on
    return;
  }
  schemes_.switched();
  // The difference to what was written fades out against the new scheme's first command.
  blend_.begin(before);
  safety_.restart_soft_start();
}

DeviceSession::ChainFault DeviceSession::chain_step(const CycleTime& cycle) {
  if (!chain_active_) {  // the first cycle, or the first after a recovery: activate from the measured state
    if (const Outcome o = activate_scheme(schemes_.active()); !o.ok()) return {DeviceFault::activation, o.reason};
    schemes_.entered();
    chain_active_ = true;
    safety_.restart_soft_start();
  } else {
    switch_scheme_if_requested();
  }
  // The supervisor's speed and workspace checks on the measured state, before the chain renders anything.
  if (const DeviceFault f = safety_.begin_cycle(state_.joints.velocity, estimator_.state(), group_force_);
      f != DeviceFault::none)
    return {f};
  engine_.take(cycle, teleop_ ? teleop_->input() : nullptr);
  SchemeChain& scheme = schemes_.active();
  if (scheme.virtual_model) {
    if (const Outcome o =
            (*scheme.virtual_model)
                ->update(cycle, VirtualModelInput{state_, estimator_.state(), engine_.input(), safety_.guard()}, task_);
        !o.ok())
      return {DeviceFault::virtual_model, o.reason};
    if (!is_finite(task_)) return {DeviceFault::non_finite_output, "the virtual model's target is not finite"};
    if (task_.has_wrench && !safety_.guard().limit_applied()) {
      // A model that does not apply the rendered-wrench limits itself: the server applies them here.
      RenderGuard::Vector6 w;
      w << task_.wrench.force, task_.wrench.torque;
      w = safety_.guard().limit(w);
      task_.wrench.force = w.head<3>();
      task_.wrench.torque = w.tail<3>();
    }
  } else {
    task_ = TaskTarget{};  // a scheme without a virtual model renders nothing (free space)
  }
  if (scheme.inverse_kinematics) {
    if (const Outcome o = (*scheme.inverse_kinematics)
                              ->update(cycle, InverseKinematicsInput{state_, task_, estimator_.state()}, joint_target_);
        !o.ok())
      return {DeviceFault::inverse_kinematics, o.reason};
    if (!is_finite(joint_target_))
      return {DeviceFault::non_finite_output, "the inverse kinematics' joint target is not finite"};
  }
  if (const Outcome o = scheme.controller->update(
          cycle, ControllerInput{state_, task_, joint_target_, estimator_.state(), redundancy_of(scheme)}, command_);
      !o.ok())
    return {DeviceFault::controller, o.reason};
  if (!command_.torque_nm.allFinite()) return {DeviceFault::non_finite_output, "the controller's torque is not finite"};
  blend_.apply(command_.torque_nm);
  return {};
}

void DeviceSession::publish_snapshot(const CycleTime& cycle, double torque_scale) noexcept {
  const bool publish = snapshot_interval_ != 0 && cycle.index % snapshot_interval_ == 0;
  const bool view = view_interval_ != 0 && cycle.index % view_interval_ == 0;
  if (!publish && !view && !snapshot_every_cycle_) return;
  DeviceSnapshot& s = snapshot_;
  s.cycle = cycle.index;
  s.time_ns = cycle.time_ns;
  s.handle_pose = estimator_.state().handle_pose;
  s.handle_twist = estimator_.state().handle_twist;
  s.operator_wrench = estimator_.state().operator_wrench;
  s.environment_wrench = task_.wrench;
  s.target_pose = task_.pose;
  s.position = state_.joints.position;
  s.velocity = state_.joints.velocity;
  s.torque = command_.torque_nm;
  s.buttons = state_.handle.buttons;
  s.gripper = state_.handle.gripper;
  s.fault = status_.fault();
  s.fault_reason = status_.fault_reason_.load(std::memory_order_relaxed);
  s.faults = status_.faults_.load(std::memory_order_relaxed);
  s.estop = s.fault == DeviceFault::emergency_stop;
  s.stopping = torque_scale < 1.0;
  s.saturated = estimator_.state().output_saturated;
  s.switching = blend_.active();
  s.scheme = static_cast<int>(schemes_.active_index());
  s.engine_weight = engine_.input().weight;
  s.engine_stale = engine_.stale();
  s.engine_sequence = engine_.input().sequence;
  s.engine_has_proxy = engine_.input().has_proxy;
  s.engine_proxy_pose = engine_.input().proxy_pose;
  s.engine_has_wrench = engine_.input().has_wrench;
  s.engine_wrench = engine_.input().wrench;
  s.safe_damping = (s.fault != DeviceFault::none || stopped_) && !safety_.at_rest();
  s.stopping = s.stopping || stopped_;
  const std::uint32_t flags = safety_.flags();
  s.limit_engaged = (flags & state_flag::limit_engaged) != 0;
  s.render_limited = (flags & state_flag::render_limited) != 0;
  s.thermal_derating = (flags & state_flag::thermal_derating) != 0;
  s.thermal_load = safety_.thermal().max_load();
  s.dissipated_j = safety_.guard().dissipated_j();
  s.passivity_control = safety_.guard().passivity_control();
  if (publish) status_.snapshots_.publish(s);
  if (view) status_.view_snapshots_.publish(s);
}

void DeviceSession::enable_teleoperation(teleop::Role role, const teleop::LinkSettings& settings) {
  teleop_ = std::make_unique<TeleopPhase>(role, settings);
  requests_.teleop_ = teleop_.get();
}

void DeviceSession::read_and_estimate(const CycleTime& cycle, std::uint32_t consecutive_overruns,
                                      std::int64_t lateness_ns) noexcept {
  if (const int p = requests_.passivity_request_.exchange(-1, std::memory_order_acquire); p >= 0) {
    safety_.guard().set_passivity_control(p == 1);
    status_.passivity_control_.store(p == 1, std::memory_order_release);
  }
  Outcome read = Outcome::failure("read() threw an exception");
  try {
    read = chain_.device->read(cycle, state_);
  } catch (...) {
  }
  // The watchdogs and requests that stop the device.
  if (const std::uint64_t estops = requests_.estop_requests_.load(std::memory_order_acquire);
      estops != estops_handled_) {
    estops_handled_ = estops;
    if (status_.fault() == DeviceFault::none && !stopped_) {
      raise_fault(DeviceFault::emergency_stop, cycle);
    } else {
      relatch_emergency_stop(cycle);  // already safe: the stop is logged and voids any pending recovery
    }
  }
  if (status_.fault() == DeviceFault::none && !stopped_ && safety_.overruns_exceeded(consecutive_overruns))
    raise_fault(DeviceFault::loop_overrun, cycle);
  if (status_.fault() == DeviceFault::none && !stopped_ && safety_.stalled(lateness_ns))
    raise_fault(DeviceFault::loop_stall, cycle);
  if (status_.fault() == DeviceFault::none && !stopped_ &&
      requests_.safe_stop_requested_.load(std::memory_order_acquire)) {
    stopped_ = true;
    leave_chain();
    safety_.enter_safe_mode(last_written_, estimator_.has_model() ? &state_.joints.position : nullptr,
                            true);  // stopping: no hold
    status_.at_rest_.store(false, std::memory_order_release);
  }
  // The measurement: a running device faults on a read error, a non-finite value or a saturated sensor; in the
  // safe mode it is estimated as long as its positions can be trusted (an arm that sags is seen).
  measurement_valid_ = read.ok() && state_.joints.position.allFinite();
  if (status_.fault() == DeviceFault::none && !stopped_) {
    if (!read.ok()) {
      raise_fault(DeviceFault::device_read, cycle, read.reason);
    } else if (!is_finite(state_)) {
      measurement_valid_ = false;
      raise_fault(DeviceFault::non_finite_measurement, cycle);
    } else if (state_.sensor_saturated) {
      raise_fault(DeviceFault::sensor_saturation, cycle);
    }
  }
  safe_path_ = status_.fault() != DeviceFault::none || stopped_;
  if (measurement_valid_) estimate(cycle);
  estimator_.state().neighbour = NeighbourClearance{};  // the group stage, next, finds this cycle's
  if (teleop_) {
    // The teleoperation link's side on this state: its force reaches the chain in this cycle, a stop it decides at
    // the next (the E-stop, as any door's).
    teleop_->cycle(cycle.time_ns, estimator_.state(), status_.fault() != DeviceFault::none, ending_ || stopped_);
    if (teleop_->stop() != teleop::PortStop::none) requests_.emergency_stop();
  }
  group_force_.setZero();
}

void DeviceSession::estimate(const CycleTime& cycle) noexcept {
  // The velocity estimate starts again from this sample when the chain (re)activates from the measured state.
  estimator_.estimate(state_, cycle.time_ns, cycle.period_ns, !safe_path_ && !chain_active_);
}

void DeviceSession::run_chain(const CycleTime& cycle) noexcept {
  if (safe_path_) return;
  ChainFault chain_fault;
  try {
    chain_fault = chain_step(cycle);
  } catch (...) {
    chain_fault = {DeviceFault::plugin_exception, "a plugin of the chain threw an exception in update()"};
  }
  if (chain_fault.fault == DeviceFault::none) return;
  raise_fault(chain_fault.fault, cycle, chain_fault.reason);
  safe_path_ = true;
}

void DeviceSession::limit_and_write(const CycleTime& cycle, double torque_scale) noexcept {
  ending_ = torque_scale < 1.0;  // the session's planned end: the teleoperation link's next cycle applies no force
  if (safe_path_) {
    safe_mode_step(cycle);
  } else {
    bool saturated = false;
    safety_.limit(state_.joints.velocity, estimator_.state(), command_.torque_nm, saturated);
    estimator_.state().output_saturated = saturated;
    if (saturated) status_.saturated_cycles_.fetch_add(1, std::memory_order_relaxed);
    const std::uint32_t flags = safety_.flags();
    if ((flags & state_flag::limit_engaged) != 0) status_.limited_cycles_.fetch_add(1, std::memory_order_relaxed);
    if ((flags & state_flag::render_limited) != 0)
      status_.render_limited_cycles_.fetch_add(1, std::memory_order_relaxed);
    const double scale = std::clamp(torque_scale, 0.0, 1.0);
    if (scale > 0.0) {
      command_.torque_nm *= scale;
    } else {
      command_.torque_nm.setZero();  // exactly +0, not -0 from a negative torque times zero
    }
    const Outcome written = write_device(cycle);
    if (written.ok()) {
      last_written_ = command_.torque_nm;
      safety_.written(command_.torque_nm);
      status_.dissipated_j_.store(safety_.guard().dissipated_j(), std::memory_order_relaxed);
      status_.thermal_load_.store(safety_.thermal().max_load(), std::memory_order_relaxed);
    } else {
      last_written_.setZero();  // unknown what the drive holds: do not fade from it
      raise_fault(DeviceFault::device_write, cycle, written.reason);
      safe_path_ = true;
      safe_mode_step(cycle);
    }
  }
  record_history(cycle);
  publish_snapshot(cycle, torque_scale);
}

Outcome DeviceSession::write_device(const CycleTime& cycle) noexcept {
  try {
    if (description_.interface == DeviceInterface::handle)
      return chain_.device->write_handle(cycle, handle_command(description_.handle, command_.torque_nm));
    return chain_.device->write(cycle, command_);
  } catch (...) {
    return Outcome::failure("write() threw an exception");
  }
}

void DeviceSession::safe_mode_step(const CycleTime& cycle) noexcept {
  // Joint damping (and, with a robot model, gravity compensation holding the posture) while the measurement can
  // be trusted, then zero torque.
  const JointVector* gravity = estimator_.gravity_torque();
  const bool valid =
      measurement_valid_ && state_.joints.velocity.allFinite() && (gravity == nullptr || gravity->allFinite());
  safety_.safe_torque(state_.joints.position, state_.joints.velocity, valid, gravity, command_.torque_nm);
  status_.at_rest_.store(safety_.at_rest(), std::memory_order_release);
  (void)write_device(cycle);
  last_written_ = command_.torque_nm;
  if (safety_.at_rest() && !braked_) {
    // At rest with zero torque: the device's brakes hold it (a handle device's, a joint device's holding brakes);
    // a device that cannot brake now (unplugged) is asked again next cycle.
    try {
      braked_ = chain_.device->brake(true).ok();
    } catch (...) {
    }
  }
  recover_if_requested(cycle);
}

void DeviceSession::recover_if_requested(const CycleTime& cycle) noexcept {
  if (stopped_ || !safety_.settled()) return;
  std::uint64_t wanted = requests_.recovery_for_epoch_.load(std::memory_order_acquire);
  // Only a request made after the last stop: a stop since then (requests_.stop_epoch_ moved on) voids it.
  if (wanted == 0 || wanted != requests_.stop_epoch_.load(std::memory_order_acquire) + 1) return;
  if (requests_.estop_requests_.load(std::memory_order_acquire) != estops_handled_) return;  // a stop not handled yet
  // The scheme that ran must have been deactivated off the loop (service()) before it activates again.
  if (!schemes_.active_idle()) return;
  if (!requests_.recovery_for_epoch_.compare_exchange_strong(wanted, 0, std::memory_order_acq_rel)) return;
  // The drives' latched fault is cleared first; if it cannot be, the device stays safe and says why (the
  // request is used up: a new one tries again).
  Outcome reset = Outcome::failure("reset_fault() threw an exception");
  try {
    reset = chain_.device->reset_fault();
  } catch (...) {
  }
  if (!reset.ok()) {
    status_.fault_reason_.store(reason_or_null(reset.reason), std::memory_order_relaxed);
    status_.refused_recoveries_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  if (braked_) {
    Outcome released = Outcome::failure("brake(false) threw an exception");
    try {
      released = chain_.device->brake(false);
    } catch (...) {
    }
    if (!released.ok()) {
      status_.fault_reason_.store(reason_or_null(released.reason), std::memory_order_relaxed);
      status_.refused_recoveries_.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    braked_ = false;
  }
  status_.fault_reason_.store(nullptr, std::memory_order_relaxed);
  chain_active_ = false;  // the next cycle activates the chain from the measured state, with a soft start
  // Whatever the safe mode holds (gravity, damping) fades out against the chain's first commands: no step.
  if (last_written_.isZero(0.0)) {
    blend_.cancel();
  } else {
    blend_.begin(last_written_);
  }
  engine_.restart();  // engine input ramps in again
  status_.recoveries_.fetch_add(1, std::memory_order_relaxed);
  log_safety_event(SafetyEvent::Kind::recovery, status_.fault(), cycle);
  status_.fault_.store(DeviceFault::none, std::memory_order_release);
}

void DeviceSession::record_history(const CycleTime& cycle) noexcept {
  HistoryRecord r;
  r.cycle = cycle.index;
  r.time_ns = cycle.time_ns;
  r.position = state_.joints.position;
  r.velocity = state_.joints.velocity;
  r.torque = command_.torque_nm;
  r.handle_position = estimator_.state().handle_pose.position;
  r.handle_velocity = estimator_.state().handle_twist.linear;
  r.operator_force = estimator_.state().operator_wrench.force;
  r.environment_force = task_.wrench.force;
  r.flags = safety_.flags();
  safety_.history().record(r);
}

void DeviceSession::leave_chain() noexcept {
  // The running scheme leaves the loop (service() deactivates it); a recovery activates it again.
  if (!chain_active_) return;
  schemes_.left();
  chain_active_ = false;
}

void DeviceSession::log_safety_event(SafetyEvent::Kind kind, DeviceFault fault, const CycleTime& cycle) noexcept {
  if (!status_.safety_events_.try_push(SafetyEvent{kind, fault, cycle.index, cycle.time_ns}))
    status_.lost_safety_events_.fetch_add(1, std::memory_order_relaxed);
}

void DeviceSession::publish_fault(DeviceFault fault, const CycleTime& cycle, const char* reason) noexcept {
  // The report: the cycles before this one, as recorded (this cycle never wrote its chain's command).
  report_.fault = fault;
  report_.reason.fill('\0');
  if (reason != nullptr) {
    for (std::size_t i = 0; i + 1 < report_.reason.size() && reason[i] != '\0'; ++i) report_.reason[i] = reason[i];
  }
  status_.fault_reason_.store(reason_or_null(reason), std::memory_order_relaxed);
  report_.serial = status_.faults_.load(std::memory_order_relaxed) + 1;
  report_.cycle = cycle.index;
  report_.time_ns = cycle.time_ns;
  safety_.history().copy_to(report_);
  status_.reports_.publish(report_);
  status_.fault_cycle_.store(cycle.index, std::memory_order_relaxed);
  status_.faults_.store(report_.serial, std::memory_order_relaxed);
  log_safety_event(SafetyEvent::Kind::fault, fault, cycle);
  requests_.stop_epoch_.fetch_add(1, std::memory_order_acq_rel);  // voids a recovery asked before this fault
  status_.fault_.store(fault, std::memory_order_release);
}

void DeviceSession::relatch_emergency_stop(const CycleTime& cycle) noexcept {
  // The safe mode (or the server's stop) goes on as it is; the stop is a fault of its own.
  publish_fault(DeviceFault::emergency_stop, cycle);
}

void DeviceSession::hold_before_start(DeviceFault fault, const char* reason) noexcept {
  if (status_.fault_.load(std::memory_order_relaxed) != DeviceFault::none) return;  // a configure error came first
  status_.fault_reason_.store(reason_or_null(reason), std::memory_order_relaxed);
  status_.faults_.store(1, std::memory_order_relaxed);
  status_.fault_.store(fault, std::memory_order_release);
}

void DeviceSession::raise_fault(DeviceFault fault, const CycleTime& cycle, const char* reason) noexcept {
  publish_fault(fault, cycle, reason);
  leave_chain();
  // The last torque that reached the drives fades out, unless the measurement cannot be trusted (then the
  // damping cannot run either, and the safe mode is zero torque at once).
  safety_.enter_safe_mode(last_written_, estimator_.has_model() ? &state_.joints.position : nullptr);
  status_.at_rest_.store(safety_.at_rest(), std::memory_order_release);
}

void DeviceSession::offer_neighbour(const NeighbourClearance& neighbour) noexcept {
  NeighbourClearance& nearest = estimator_.state().neighbour;
  if (!nearest.present() || neighbour.distance_m < nearest.distance_m) nearest = neighbour;
}

void DeviceSession::raise_group_fault(DeviceFault fault, const CycleTime& cycle, const char* reason) noexcept {
  if (status_.fault_.load(std::memory_order_relaxed) != DeviceFault::none) return;
  raise_fault(fault, cycle, reason);
}

void DeviceSession::deactivate() {
  chain_active_ = false;
  {
    // Waits for a request being served, but not for good: a request thread that is stuck (a broken invariant
    // parks it) must not keep the device from being disabled.
    std::unique_lock lock(requests_.plugin_requests_, std::try_to_lock);
    for (int i = 0; i < 200 && !lock.owns_lock(); ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      lock.try_lock();
    }
    schemes_.service(true);
  }
  disable_error_.clear();
  try {
    chain_.device->disable();
  } catch (const std::exception& e) {
    disable_error_ = std::string("disable() threw: ") + e.what();
  } catch (...) {
    disable_error_ = "disable() threw an exception";
  }
}

}  // namespace hapticd::server
