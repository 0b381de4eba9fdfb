#include "openhaptics_device.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace hapticd::plugins::openhaptics {
namespace {

// The HD scheduler is one per process, shared by every device: started by the first enable(), stopped by the
// last disable().
std::mutex scheduler_mutex;
int scheduler_users = 0;

HDCallbackCode servo_callback(void* self) { return static_cast<OpenHapticsDevice*>(self)->servo(); }

}  // namespace

HdErrors HdErrors::of(const HdApi& hd) noexcept {
  HdErrors errors;
  errors.drain(hd);
  return errors;
}

void HdErrors::drain(const HdApi& hd) noexcept {
  for (int i = 0; i < 16; ++i) {
    const HDErrorInfo e = hd.get_error();
    if (e.errorCode == kSuccess) return;
    add(e);
  }
}

ParameterSchema OpenHapticsDevice::parameter_schema() {
  ParameterSchema s;
  s.string("sdk_path", "the SDK's libHD.so, or its folder; empty: OH_SDK_BASE, then the library path")
      .default_value("");
  s.string("device_name", "the device's configured name (Touch Setup), e.g. \"Default Device\"; empty: the default")
      .default_value("");
  s.real("max_force_n", "the largest force to command; 0: the device's nominal peak force")
      .unit("N")
      .minimum(0.0)
      .default_value(0.0);
  ServoHandoff<HdSample, HdCommand>::add_parameters(s);
  return s;
}

OpenHapticsDevice::~OpenHapticsDevice() { close_device(); }

void OpenHapticsDevice::configure(const Parameters& p, const PluginContext& context) {
  VendorLibrarySearch search;
  search.vendor = "OpenHaptics";
  search.names = {"libHD.so", "libHD.so.3.4", "libHD.so.3.0"};
  search.path = p.string("sdk_path");
  search.environment = "OH_SDK_BASE";
  search.subdirs = {"lib", "lib64"};
  try {
    library_ = std::make_unique<VendorLibrary>(search);
    hd_ = std::make_unique<HdApi>(*library_);
  } catch (const VendorLibraryError& e) {
    throw DeviceUnavailable(e.what());
  }
  const std::string name = p.string("device_name");
  handle_ = hd_->init_device(name.empty() ? nullptr : name.c_str());
  if (const HDErrorInfo e = hd_->get_error(); handle_ == kInvalidHandle || e.errorCode != kSuccess) {
    handle_ = kInvalidHandle;
    throw DeviceUnavailable(
        "cannot open the OpenHaptics device " + (name.empty() ? "(the default)" : "'" + name + "'") + ": " +
        vendor_text(hd_->text_of(e.errorCode)) + " (internal code " + std::to_string(e.internalErrorCode) + ")");
  }
  hd_->make_current_device(handle_);
  const std::string model = vendor_text(hd_->get_string(kDeviceModelType));

  // Calibration: an update the SDK makes itself (nothing moves); the inkwell needs the user.
  const HDenum calibration = hd_->check_calibration();
  if (calibration == kCalibrationNeedsManualInput) {
    close_device();
    throw std::runtime_error("the " + model +
                             " needs calibrating (the SDK: HD_CALIBRATION_NEEDS_MANUAL_INPUT): put the stylus into "
                             "the inkwell, or calibrate it with Touch Diagnostic, then start again");
  }
  if (calibration == kCalibrationNeedsUpdate) {
    int styles = 0;
    hd_->get_integerv(kCalibrationStyle, &styles);
    const int style = (styles & kCalibrationAuto)           ? kCalibrationAuto
                      : (styles & kCalibrationEncoderReset) ? kCalibrationEncoderReset
                                                            : kCalibrationInkwell;
    hd_->update_calibration(static_cast<HDenum>(style));
    if (const HDErrorInfo e = hd_->get_error(); e.errorCode != kSuccess) {
      close_device();
      throw std::runtime_error("the " + model +
                               " could not update its calibration: " + vendor_text(hd_->text_of(e.errorCode)));
    }
  }

  handoff_.configure(p, context.rate_hz);
  hd_->set_scheduler_rate(static_cast<unsigned long>(std::lround(context.rate_hz)));
  if (const HDErrorInfo e = hd_->get_error(); e.errorCode != kSuccess) {
    close_device();
    throw std::runtime_error("the HD scheduler cannot run at the session's rate of " + std::to_string(context.rate_hz) +
                             " Hz (" + vendor_text(hd_->text_of(e.errorCode)) +
                             "): set server.rate_hz to one it supports, e.g. 1000");
  }

  int input_dof = 0, output_dof = 0;
  hd_->get_integerv(kInputDof, &input_dof);
  hd_->get_integerv(kOutputDof, &output_dof);
  double workspace[6] = {0, 0, 0, 0, 0, 0}, max_force = 0, continuous = 0, stiffness = 0, damping = 0;
  hd_->get_doublev(kUsableWorkspaceDimensions, workspace);
  hd_->get_doublev(kNominalMaxForce, &max_force);
  hd_->get_doublev(kNominalMaxContinuousForce, &continuous);
  hd_->get_doublev(kNominalMaxStiffness, &stiffness);
  hd_->get_doublev(kNominalMaxDamping, &damping);
  const std::string serial = vendor_text(hd_->get_string(kDeviceSerialNumber), "");

  DeviceDescription& d = description_;
  d.model = "openhaptics " + model + (serial.empty() ? std::string() : " " + serial);
  d.interface = DeviceInterface::handle;
  HandleDescription& h = d.handle;
  h.senses_orientation = input_dof >= 6;
  h.buttons = 2;
  if (output_dof >= 6) {  // a PHANTOM with 6-DOF output: torques about the handle, Cartesian (HD_CURRENT_TORQUE)
    double max_torque_mnm = 0, torque_stiffness = 0, torque_damping = 0;
    hd_->get_doublev(kNominalMaxTorqueForce, &max_torque_mnm);
    hd_->get_doublev(kNominalMaxTorqueStiffness, &torque_stiffness);
    hd_->get_doublev(kNominalMaxTorqueDamping, &torque_damping);
    (void)HdErrors::of(*hd_);  // a figure the device does not report stays 0 (each one left an error)
    h.actuated_torque = max_torque_mnm > 0.0;
    h.max_torque_nm = max_torque_mnm * 1e-3;
    h.recommended_rotational_stiffness_nm_per_rad = torque_stiffness * 1e-3;
    h.recommended_rotational_damping_nm_s_per_rad = torque_damping * 1e-3;
  }
  const Eigen::Vector3d lo(workspace[0], workspace[1], workspace[2]), hi(workspace[3], workspace[4], workspace[5]);
  if ((hi - lo).minCoeff() > 0.0) {
    h.workspace_min = lo * 1e-3;
    h.workspace_max = hi * 1e-3;
  } else {
    h.workspace_min = Eigen::Vector3d::Constant(-0.08);
    h.workspace_max = Eigen::Vector3d::Constant(0.08);
  }
  if (!(max_force > 0.0)) {
    close_device();
    throw std::runtime_error("the " + model + " reports no nominal force (HD_NOMINAL_MAX_FORCE)");
  }
  const double asked = p.real("max_force_n");
  if (asked > max_force)
    throw ParameterError("max_force_n", "above the " + model + "'s nominal " + std::to_string(max_force));
  h.max_force_n = asked > 0.0 ? asked : max_force;
  h.continuous_force_n = continuous > 0.0 ? std::min(continuous, h.max_force_n) : 0.0;
  h.recommended_stiffness_n_per_m = stiffness * 1e3;  // N/mm
  h.recommended_damping_n_s_per_m = damping * 1e3;    // N s/mm
}

const char* OpenHapticsDevice::failure(const char* what, const HdErrors& errors) noexcept {
  // Each error the stack held, in the order the SDK gave them (the newest first): "the servo frame: device fault
  // (HD error 0x0300, internal 42); communication error ... (HD error 0x0302, internal 0)". The first failure since
  // the last recovery is the one told.
  std::array<char, 384>& text = errors_[static_cast<std::size_t>(error_)];
  if (text[0] != '\0') return text.data();
  int used = std::snprintf(text.data(), text.size(), "%s: ", what);
  const int shown = std::min(errors.count, static_cast<int>(errors.first.size()));
  for (int i = 0; i < shown && used > 0 && used < static_cast<int>(text.size()); ++i) {
    const HDErrorInfo& e = errors.first[static_cast<std::size_t>(i)];
    used += std::snprintf(text.data() + used, text.size() - static_cast<std::size_t>(used),
                          "%s%.200s (HD error 0x%04x, internal %d)", i > 0 ? "; " : "", hd_->text_of(e.errorCode),
                          e.errorCode, e.internalErrorCode);
  }
  if (errors.count > shown && used > 0 && used < static_cast<int>(text.size()))
    std::snprintf(text.data() + used, text.size() - static_cast<std::size_t>(used), "; %d more on the stack",
                  errors.count - shown);
  return text.data();
}

Outcome OpenHapticsDevice::enable() {
  if (handle_ == kInvalidHandle) return Outcome::failure("the OpenHaptics device is not open");
  errors_[static_cast<std::size_t>(error_)][0] = '\0';
  have_sample_ = false;
  applied_ = HdCommand{};
  handoff_.reset();
  end_errors_ = HdErrors{};
  hd_->make_current_device(handle_);
  (void)HdErrors::of(*hd_);  // nothing of configure's queries may be told as this start's, or a frame's, error
  hd_->enable(kForceOutput);
  if (const HdErrors e = HdErrors::of(*hd_); e.count > 0) return Outcome::failure(failure("enabling forces", e));
  ended_.store(false);
  running_.store(true);
  callback_ = hd_->schedule_asynchronous(&servo_callback, this, kMaxSchedulerPriority);
  if (const HdErrors e = HdErrors::of(*hd_); e.count > 0) {
    running_.store(false);
    return Outcome::failure(failure("scheduling the servo callback", e));
  }
  scheduled_ = true;
  {
    std::lock_guard lock(scheduler_mutex);
    if (scheduler_users++ == 0) hd_->start_scheduler();
  }
  if (const HdErrors e = HdErrors::of(*hd_); e.count > 0)
    return Outcome::failure(failure("starting the HD scheduler", e));
  // The first sample before the first cycle (the loop may not run on the device's clock).
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(1);
  const std::uint64_t before = handoff_.samples();
  while (handoff_.samples() == before && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  if (handoff_.samples() == before)
    return Outcome::failure("the HD scheduler did not call the servo callback within 1 s");
  return Outcome::success();
}

HDCallbackCode OpenHapticsDevice::servo() noexcept {
  if (!running_.load(std::memory_order_acquire)) {  // the end: one frame with no force, then done
    const double zero[3] = {0, 0, 0};
    hd_->begin_frame(handle_);
    hd_->set_doublev(kCurrentForce, zero);
    if (description_.handle.actuated_torque) hd_->set_doublev(kCurrentTorque, zero);
    hd_->end_frame(handle_);
    ended_.store(true, std::memory_order_release);
    return kCallbackDone;
  }
  HdSample s;
  hd_->begin_frame(handle_);
  hd_->get_doublev(kCurrentPosition, s.position_mm.data());
  hd_->get_doublev(kCurrentVelocity, s.velocity_mm_s.data());
  hd_->get_doublev(kCurrentTransform, s.transform.data());
  hd_->get_doublev(kCurrentAngularVelocity, s.angular_velocity.data());
  hd_->get_doublev(kCurrentJointAngles, s.joint_angles.data());
  hd_->get_doublev(kCurrentGimbalAngles, s.gimbal_angles.data());
  hd_->get_integerv(kCurrentButtons, &s.buttons);
  s.errors = end_errors_;  // the previous frame's end first
  s.errors.drain(*hd_);
  s.time_ns = realtime::TickSignal::now_ns();
  handoff_.publish(s, s.time_ns);
  handoff_.next_command(applied_);  // on the device's clock: the loop's answer to this tick
  hd_->set_doublev(kCurrentForce, applied_.force_n.data());
  if (description_.handle.actuated_torque) hd_->set_doublev(kCurrentTorque, applied_.torque_mnm.data());
  hd_->end_frame(handle_);
  end_errors_ = HdErrors{};  // told with the next sample
  end_errors_.drain(*hd_);
  return kCallbackContinue;
}

Outcome OpenHapticsDevice::read(const CycleTime& cycle, DeviceState& state) {
  if (handoff_.take(sample_)) have_sample_ = true;
  if (!have_sample_) return Outcome::failure("no sample from the HD scheduler yet");
  if (sample_.errors.count > 0) return Outcome::failure(failure("the servo frame", sample_.errors));
  if (realtime::TickSignal::now_ns() - sample_.time_ns > handoff_.max_sample_age_ns())
    return Outcome::failure("no sample from the HD scheduler within max_sample_age_s (it stopped calling)");
  HandleState& h = state.handle;
  state.timestamp_ns = cycle.time_ns;
  h.pose.position = Eigen::Vector3d(sample_.position_mm[0], sample_.position_mm[1], sample_.position_mm[2]) * 1e-3;
  h.twist.linear = Eigen::Vector3d(sample_.velocity_mm_s[0], sample_.velocity_mm_s[1], sample_.velocity_mm_s[2]) * 1e-3;
  if (description_.handle.senses_orientation) {
    Eigen::Matrix3d r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r(i, j) = sample_.transform[static_cast<std::size_t>(j * 4 + i)];
    h.pose.orientation = Eigen::Quaterniond(r).normalized();
    h.twist.angular =
        Eigen::Vector3d(sample_.angular_velocity[0], sample_.angular_velocity[1], sample_.angular_velocity[2]);
  }
  h.buttons = static_cast<std::uint32_t>(sample_.buttons);
  for (std::size_t i = 0; i < 3; ++i) {
    h.linkage[i] = sample_.joint_angles[i];
    h.linkage[3 + i] = sample_.gimbal_angles[i];
  }
  h.linkage_count = 6;
  return Outcome::success();
}

Outcome OpenHapticsDevice::write(const CycleTime&, const JointCommand& command) {
  const JointVector& e = command.torque_nm;
  if (e.size() != description_.handle.axes()) return Outcome::failure("the command does not match the device's axes");
  HdCommand c;
  for (std::size_t i = 0; i < 3; ++i) {
    if (!std::isfinite(e[i])) return Outcome::failure("a non-finite force");
    c.force_n[i] = e[i];
  }
  if (description_.handle.actuated_torque) {
    for (std::size_t i = 0; i < 3; ++i) {
      if (!std::isfinite(e[3 + i])) return Outcome::failure("a non-finite torque");
      c.torque_mnm[i] = e[3 + i] * 1e3;
    }
  }
  handoff_.command(c);
  return Outcome::success();
}

Outcome OpenHapticsDevice::reset_fault() {
  // A recovery: the next failure says its own reason, in the other buffer.
  error_ = 1 - error_;
  errors_[static_cast<std::size_t>(error_)][0] = '\0';
  return Outcome::success();
}

void OpenHapticsDevice::disable() { close_device(); }

void OpenHapticsDevice::close_device() noexcept {
  if (!hd_ || handle_ == kInvalidHandle) return;
  running_.store(false, std::memory_order_release);
  if (scheduled_) {
    // The callback's last frame writes no force (on the scheduler's thread, where frames belong); 0.1 s at most.
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(100);
    while (!ended_.load(std::memory_order_acquire) && std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    hd_->unschedule(callback_);
    scheduled_ = false;
    std::lock_guard lock(scheduler_mutex);
    if (--scheduler_users == 0) hd_->stop_scheduler();
  }
  hd_->make_current_device(handle_);
  hd_->disable(kForceOutput);
  hd_->disable_device(handle_);
  (void)HdErrors::of(*hd_);
  handle_ = kInvalidHandle;
}

}  // namespace hapticd::plugins::openhaptics
