#include "openhaptics_device.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <thread>

#include "hapticd/realtime/tick_signal.hpp"

namespace hapticd::plugins::openhaptics {

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
  s.real("open_timeout_s", "how long opening the device and reading its figures may take before it is given up")
      .unit("s")
      .greater_than(0.0)
      .maximum(600.0)
      .default_value(10.0);
  ServoHandoff<HdSample, HdCommand>::add_parameters(s);
  return s;
}

OpenHapticsDevice::~OpenHapticsDevice() {
  close_device();
  // A call still stuck in the SDK keeps the link (the library, the callback's state) alive with its thread.
  if (link_) (void)link_->sdk.stop(0.0, link_);
}

void OpenHapticsDevice::run_once(const char* timeout_key, double seconds) {
  if (link_->sdk.run(link_->once, seconds)) return;
  const char* call = link_->sdk.stuck_in();
  throw DeviceUnavailable(std::string("the OpenHaptics SDK did not return from ") +
                          (call[0] != '\0' ? call : "a call") + " within " + timeout_key + " (" +
                          std::to_string(seconds) +
                          " s): the device or its connection does not answer; the server does not use it");
}

void OpenHapticsDevice::configure(const Parameters& p, const PluginContext& context) {
  VendorLibrarySearch search;
  search.vendor = "OpenHaptics";
  search.names = {"libHD.so", "libHD.so.3.4", "libHD.so.3.0"};
  search.path = p.string("sdk_path");
  search.environment = "OH_SDK_BASE";
  search.subdirs = {"lib", "lib64"};
  try {
    link_ = std::make_shared<HdLink>(std::make_unique<VendorLibrary>(search));
  } catch (const VendorLibraryError& e) {
    throw DeviceUnavailable(e.what());
  }
  HdLink& l = *link_;
  const double open_s = p.real("open_timeout_s");
  const std::string name = p.string("device_name");
  std::string open_error;
  // Open, then what the device says of itself; the calibration checked. On the SDK's thread, with a deadline.
  l.once = [&l, name, rate = std::lround(context.rate_hz)] {
    const HdApi& hd = *l.hd;
    HdFacts& f = l.facts;
    l.failed = "";
    l.sdk.calling("hdInitDevice");
    l.handle = hd.init_device(name.empty() ? nullptr : name.c_str());
    if (const HDErrorInfo e = hd.get_error(); l.handle == kInvalidHandle || e.errorCode != kSuccess) {
      l.handle = kInvalidHandle;
      l.errors = HdErrors{};
      l.errors.add(e);
      l.failed = "hdInitDevice";
      return;
    }
    l.sdk.calling("hdMakeCurrentDevice");
    hd.make_current_device(l.handle);
    l.sdk.calling("hdGetString");
    f.model = vendor_text(hd.get_string(kDeviceModelType));
    f.serial = vendor_text(hd.get_string(kDeviceSerialNumber), "");
    f.version = vendor_text(hd.get_string(kVersion), "");
    f.driver = vendor_text(hd.get_string(kDeviceDriverVersion), "");
    (void)HdErrors::of(hd);  // a string the SDK does not report leaves an error: not this device's fault
    l.sdk.calling("hdCheckCalibration");
    f.calibration = hd.check_calibration();
    if (f.calibration == kCalibrationNeedsUpdate) {
      int styles = 0;
      hd.get_integerv(kCalibrationStyle, &styles);
      const int style = (styles & kCalibrationAuto)           ? kCalibrationAuto
                        : (styles & kCalibrationEncoderReset) ? kCalibrationEncoderReset
                                                              : kCalibrationInkwell;
      l.sdk.calling("hdUpdateCalibration");
      hd.update_calibration(static_cast<HDenum>(style));
      if (l.errors = HdErrors::of(hd); l.errors.count > 0) {
        l.failed = "hdUpdateCalibration";
        return;
      }
    }
    l.sdk.calling("hdSetSchedulerRate");
    hd.set_scheduler_rate(static_cast<unsigned long>(rate));
    if (l.errors = HdErrors::of(hd); l.errors.count > 0) {
      l.failed = "hdSetSchedulerRate";
      return;
    }
    l.sdk.calling("hdGetDoublev");
    hd.get_integerv(kInputDof, &f.input_dof);
    hd.get_integerv(kOutputDof, &f.output_dof);
    hd.get_doublev(kUsableWorkspaceDimensions, f.workspace);
    hd.get_doublev(kNominalMaxForce, &f.max_force);
    hd.get_doublev(kNominalMaxContinuousForce, &f.continuous);
    hd.get_doublev(kNominalMaxStiffness, &f.stiffness);
    hd.get_doublev(kNominalMaxDamping, &f.damping);
    if (f.output_dof >= 6) {
      hd.get_doublev(kNominalMaxTorqueForce, &f.max_torque_mnm);
      hd.get_doublev(kNominalMaxTorqueStiffness, &f.torque_stiffness);
      hd.get_doublev(kNominalMaxTorqueDamping, &f.torque_damping);
      (void)HdErrors::of(hd);  // a figure the device does not report stays 0 (each one left an error)
    }
  };
  run_once("open_timeout_s", open_s);
  const HdFacts& f = l.facts;
  const std::string failed = l.failed;
  const std::string sdk_text =
      l.errors.count > 0 ? vendor_text(l.hd->text_of(l.errors.first[0].errorCode)) : std::string("no error");
  if (failed == "hdInitDevice")
    throw DeviceUnavailable("cannot open the OpenHaptics device " +
                            (name.empty() ? "(the default)" : "'" + name + "'") + ": " + sdk_text + " (internal code " +
                            std::to_string(l.errors.first[0].internalErrorCode) + ")");
  const std::string model = f.model;
  // Calibration: an update the SDK makes itself (nothing moves); the inkwell needs the user.
  if (f.calibration == kCalibrationNeedsManualInput) {
    close_device();
    throw std::runtime_error("the " + model +
                             " needs calibrating (the SDK: HD_CALIBRATION_NEEDS_MANUAL_INPUT): put the stylus into "
                             "the inkwell, or calibrate it with Touch Diagnostic, then start again");
  }
  if (failed == "hdUpdateCalibration") {
    close_device();
    throw std::runtime_error("the " + model + " could not update its calibration: " + sdk_text);
  }
  if (failed == "hdSetSchedulerRate") {
    close_device();
    throw std::runtime_error("the HD scheduler cannot run at the session's rate of " + std::to_string(context.rate_hz) +
                             " Hz (" + sdk_text + "): set server.rate_hz to one it supports, e.g. 1000");
  }
  l.handoff.configure(p, context.rate_hz);

  DeviceDescription& d = description_;
  d.model = "openhaptics " + model + (f.serial.empty() ? std::string() : " " + f.serial);
  d.serial = f.serial;
  d.vendor_software = "OpenHaptics HD" + (f.version.empty() ? std::string() : " " + f.version) +
                      (f.driver.empty() ? std::string() : ", driver " + f.driver) + ", " + l.library->file();
  d.interface = DeviceInterface::handle;
  HandleDescription& h = d.handle;
  h.senses_orientation = f.input_dof >= 6;
  h.buttons = 2;
  if (f.output_dof >= 6) {  // a PHANTOM with 6-DOF output: torques about the handle, Cartesian (HD_CURRENT_TORQUE)
    h.actuated_torque = f.max_torque_mnm > 0.0;
    h.max_torque_nm = f.max_torque_mnm * 1e-3;
    h.recommended_rotational_stiffness_nm_per_rad = f.torque_stiffness * 1e-3;
    h.recommended_rotational_damping_nm_s_per_rad = f.torque_damping * 1e-3;
  }
  l.actuated_torque = h.actuated_torque;
  const Eigen::Vector3d lo(f.workspace[0], f.workspace[1], f.workspace[2]),
      hi(f.workspace[3], f.workspace[4], f.workspace[5]);
  if ((hi - lo).minCoeff() > 0.0) {
    h.workspace_min = lo * 1e-3;
    h.workspace_max = hi * 1e-3;
  } else {
    h.workspace_min = Eigen::Vector3d::Constant(-0.08);
    h.workspace_max = Eigen::Vector3d::Constant(0.08);
  }
  if (!(f.max_force > 0.0)) {
    close_device();
    throw std::runtime_error("the " + model + " reports no nominal force (HD_NOMINAL_MAX_FORCE)");
  }
  const double asked = p.real("max_force_n");
  if (asked > f.max_force)
    throw ParameterError("max_force_n", "above the " + model + "'s nominal " + std::to_string(f.max_force));
  h.max_force_n = asked > 0.0 ? asked : f.max_force;
  h.continuous_force_n = f.continuous > 0.0 ? std::min(f.continuous, h.max_force_n) : 0.0;
  h.recommended_stiffness_n_per_m = f.stiffness * 1e3;  // N/mm
  h.recommended_damping_n_s_per_m = f.damping * 1e3;    // N s/mm
}

const char* OpenHapticsDevice::failure(const char* what, const HdErrors& errors) noexcept {
  // Each error the stack held, in the order the SDK gave them (the newest first): "the servo frame: device fault
  // (HD error 0x0300, internal 42); communication error ... (HD error 0x0302, internal 0)". The first failure since
  // the last recovery is the one told.
  return failure_text_.keep_with([&](char* text, std::size_t size) {
    int used = std::snprintf(text, size, "%s: ", what);
    const int shown = std::min(errors.count, static_cast<int>(errors.first.size()));
    for (int i = 0; i < shown && used > 0 && used < static_cast<int>(size); ++i) {
      const HDErrorInfo& e = errors.first[static_cast<std::size_t>(i)];
      used +=
          std::snprintf(text + used, size - static_cast<std::size_t>(used), "%s%.200s (HD error 0x%04x, internal %d)",
                        i > 0 ? "; " : "", link_->hd->text_of(e.errorCode), e.errorCode, e.internalErrorCode);
    }
    if (errors.count > shown && used > 0 && used < static_cast<int>(size))
      std::snprintf(text + used, size - static_cast<std::size_t>(used), "; %d more on the stack", errors.count - shown);
  });
}

Outcome OpenHapticsDevice::enable() {
  if (!link_ || link_->handle == kInvalidHandle) return Outcome::failure("the OpenHaptics device is not open");
  HdLink& l = *link_;
  failure_text_.clear();
  have_sample_ = false;
  if (l.sdk.busy()) return Outcome::failure("the OpenHaptics SDK has not returned from an earlier call");
  l.handoff.reset();
  l.once = [&l] { l.start(); };
  if (!l.sdk.run(l.once, 2.0)) {
    const char* call = l.sdk.stuck_in();
    char reason[160];
    std::snprintf(reason, sizeof reason, "the OpenHaptics SDK did not return from %s within 2 s",
                  call[0] != '\0' ? call : "a call");
    return Outcome::failure(failure(reason, HdErrors{}));
  }
  if (l.failed[0] != '\0') return Outcome::failure(failure(l.failed, l.errors));
  // The first sample before the first cycle (the loop may not run on the device's clock).
  const std::int64_t until = realtime::TickSignal::now_ns() + 1'000'000'000;
  const std::uint64_t before = l.handoff.samples();
  while (l.handoff.samples() == before && realtime::TickSignal::now_ns() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  if (l.handoff.samples() == before)
    return Outcome::failure("the HD scheduler did not call the servo callback within 1 s");
  return Outcome::success();
}

Outcome OpenHapticsDevice::read(const CycleTime& cycle, DeviceState& state) {
  ServoHandoff<HdSample, HdCommand>& handoff = link_->handoff;
  if (handoff.take(sample_)) have_sample_ = true;
  if (!have_sample_) return Outcome::failure("no sample from the HD scheduler yet");
  if (sample_.errors.count > 0) return Outcome::failure(failure("the servo frame", sample_.errors));
  if (realtime::TickSignal::now_ns() - sample_.time_ns > handoff.max_sample_age_ns())
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

Outcome OpenHapticsDevice::write_handle(const CycleTime&, const HandleCommand& command) {
  HdCommand c;  // (finite and bounded: the server's safety layer made it so)
  for (std::size_t i = 0; i < 3; ++i) {
    c.force_n[i] = command.force_n[static_cast<Eigen::Index>(i)];
    c.torque_mnm[i] = command.torque_nm[static_cast<Eigen::Index>(i)] * 1e3;  // zero without actuated torque
  }
  link_->handoff.command(c);
  return Outcome::success();
}

Outcome OpenHapticsDevice::reset_fault() {
  failure_text_.new_episode();  // the next failure says its own reason
  return Outcome::success();
}

void OpenHapticsDevice::disable() { close_device(); }

void OpenHapticsDevice::close_device() noexcept {
  if (!link_ || link_->handle == kInvalidHandle) return;
  // On the SDK's thread, 1 s at most; a call that hangs is left to it (the device's own watchdog stops its motors).
  if (!link_->sdk.wait(realtime::TickSignal::now_ns() + 1'000'000'000)) return;
  HdLink& l = *link_;
  l.once = [&l] { l.close(); };
  (void)l.sdk.run(l.once, 1.0);
}

}  // namespace hapticd::plugins::openhaptics
