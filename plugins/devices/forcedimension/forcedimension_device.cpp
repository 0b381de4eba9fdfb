#include "forcedimension_device.hpp"

#include <cstdio>
#include <stdexcept>
#include <string_view>

#include "hapticd/realtime/tick_signal.hpp"

namespace hapticd::plugins::forcedimension {
namespace {

// Nominal figures of each model from the vendor's product pages (translation workspace as a box around the
// centre, the largest force, torque and gripper force); the parameters may lower them. The recommended
// stiffness is the vendor's published closed-loop stiffness where one is given; the damping is the project's
// choice (a tenth of the stiffness's square root times the handle's mass scale - about critical for a 0.2 kg
// handle), to be lowered if a lab's unit buzzes.
struct ModelFigures {
  std::string_view name;
  bool orientation, torque, gripper;
  double half_x, half_yz;  // m
  double force_n, torque_nm, gripper_n;
  double stiffness, damping, rotational_stiffness, rotational_damping;
};
constexpr ModelFigures kModels[] = {
    {"omega.3", false, false, false, 0.055, 0.08, 12.0, 0.0, 0.0, 14500.0, 20.0, 0.0, 0.0},
    {"omega.6", true, false, false, 0.055, 0.08, 12.0, 0.0, 0.0, 14500.0, 20.0, 0.0, 0.0},
    {"omega.7", true, false, true, 0.055, 0.08, 12.0, 0.0, 8.0, 14500.0, 20.0, 0.0, 0.0},
    {"sigma.7", true, true, true, 0.065, 0.095, 20.0, 0.4, 8.0, 14500.0, 20.0, 2.0, 0.02},
    {"delta.3", false, false, false, 0.13, 0.2, 20.0, 0.0, 0.0, 14500.0, 30.0, 0.0, 0.0},
    {"delta.6", true, true, false, 0.13, 0.2, 20.0, 0.15, 0.0, 14500.0, 30.0, 1.0, 0.01},
    {"lambda.7", true, true, true, 0.065, 0.12, 20.0, 0.3, 8.0, 14500.0, 20.0, 2.0, 0.02},
};

const ModelFigures* figures_of(std::string_view system_name) {
  for (const ModelFigures& m : kModels)
    if (system_name.substr(0, m.name.size()) == m.name) return &m;
  return nullptr;
}

}  // namespace

ParameterSchema ForceDimensionDevice::parameter_schema() {
  ParameterSchema s;
  s.string("sdk_path", "the SDK's libdrd.so / libdhd.so, or its folder; empty: FORCEDIM_SDK, then the library path")
      .default_value("");
  s.integer("index", "the device's index among those connected (0: the first); used when serial is 0")
      .minimum(0)
      .maximum(15)
      .default_value(0);
  s.integer("serial", "open the device with this serial number (0: by index)").minimum(0).default_value(0);
  s.boolean("calibrate", "an uncalibrated device is calibrated by the robotic SDK (drdAutoInit; it moves!)")
      .default_value(false);
  s.string("gravity_compensation",
           "the device's own gravity compensation, or none (the server adds none on handle devices)")
      .choices({"device", "off"})
      .default_value("device");
  s.real("max_force_n", "the largest force to command; 0: the model's nominal")
      .unit("N")
      .minimum(0.0)
      .default_value(0.0);
  s.real("max_torque_nm", "the largest torque to command; 0: the model's nominal")
      .unit("N m")
      .minimum(0.0)
      .default_value(0.0);
  s.real("call_deadline_ms",
         "how long the loop waits for the SDK's calls of one cycle; a call that has not returned by then faults the "
         "device, naming it")
      .unit("ms")
      .greater_than(0.0)
      .maximum(5000.0)
      .default_value(20.0);
  s.real("open_timeout_s", "how long opening the device may take before it is given up")
      .unit("s")
      .greater_than(0.0)
      .maximum(600.0)
      .default_value(10.0);
  s.real("calibration_timeout_s", "how long the SDK's calibration (calibrate: true) may take")
      .unit("s")
      .greater_than(0.0)
      .maximum(600.0)
      .default_value(120.0);
  s.real("max_gripper_force_n", "the largest gripper force; 0: the model's nominal")
      .unit("N")
      .minimum(0.0)
      .default_value(0.0);
  return s;
}

ForceDimensionDevice::~ForceDimensionDevice() {
  close_device();
  // A job still stuck in the SDK keeps the link (and the library) alive with its thread.
  if (link_) (void)link_->sdk.stop(0.0, link_);
}

void ForceDimensionDevice::run_once(const char* call, const char* timeout_key, double seconds) {
  if (link_->sdk.run(link_->once, seconds)) return;
  throw DeviceUnavailable(std::string("the Force Dimension SDK did not return from ") + call + " within " +
                          timeout_key + " (" + std::to_string(seconds) +
                          " s): the device or its USB connection does not answer; the server does not use it");
}

void ForceDimensionDevice::configure(const Parameters& p, const PluginContext& context) {
  VendorLibrarySearch search;
  search.vendor = "Force Dimension SDK";
  search.names = {"libdrd.so.3", "libdrd.so", "libdhd.so.3", "libdhd.so"};
  search.path = p.string("sdk_path");
  search.environment = "FORCEDIM_SDK";
  search.subdirs = {"lib", "lib/release/lin-x86_64-gcc"};
  try {
    link_ = std::make_shared<DhdLink>(std::make_unique<VendorLibrary>(search));
  } catch (const VendorLibraryError& e) {
    throw DeviceUnavailable(e.what());
  }
  deadline_ns_ = static_cast<std::int64_t>(p.real("call_deadline_ms") * 1e6);
  period_ns_ = static_cast<std::int64_t>(1e9 / context.rate_hz);
  DhdLink& l = *link_;
  const double open_s = p.real("open_timeout_s");
  const long long serial = p.integer("serial");
  const char index = static_cast<char>(p.integer("index"));
  l.once = [&l, serial, index] {
    l.sdk.calling(serial > 0 ? "dhdOpenSerial" : "dhdOpenID");
    l.opened = serial > 0 ? l.dhd->open_serial(static_cast<int>(serial)) : l.dhd->open_id(index);
    l.once_error = vendor_text(l.dhd->last_error());
    l.open = l.opened >= 0;
    if (l.open) {
      l.id = static_cast<char>(l.opened);
      l.sdk.calling("dhdGetSystemName");
      l.system_name = vendor_text(l.dhd->get_system_name(l.id));
      if (l.dhd->get_serial_number != nullptr) {
        l.sdk.calling("dhdGetSerialNumber");
        unsigned short sn = 0;
        if (l.dhd->get_serial_number(&sn, l.id) >= 0) l.serial_number = sn;
      }
      if (l.dhd->get_sdk_version != nullptr) {
        l.sdk.calling("dhdGetSDKVersion");
        l.dhd->get_sdk_version(&l.sdk_version[0], &l.sdk_version[1], &l.sdk_version[2], &l.sdk_version[3]);
      }
      l.sdk.calling("dhdHasGripper");
      l.has_gripper = l.dhd->has_gripper(l.id);
      l.sdk.calling("drdIsInitialized");
      l.calibrated = l.dhd->drd_is_initialized == nullptr || l.dhd->drd_is_initialized(l.id);
    } else {
      l.sdk.calling("dhdGetDeviceCount");
      l.device_count = l.dhd->get_device_count();
    }
  };
  run_once(serial > 0 ? "dhdOpenSerial" : "dhdOpenID", "open_timeout_s", open_s);
  if (!l.open) {
    const std::string which =
        serial > 0 ? "serial number " + std::to_string(serial) : "index " + std::to_string(p.integer("index"));
    throw DeviceUnavailable("no Force Dimension device with " + which + " (" + std::to_string(l.device_count) +
                            " connected): " + l.once_error);
  }
  const std::string system = l.system_name;
  const ModelFigures* m = figures_of(system);
  if (m == nullptr) {
    close_device();
    throw std::runtime_error("Force Dimension device '" + system +
                             "' is not one this plugin knows (omega.3/6/7, sigma.7, delta.3/6, lambda.7)");
  }
  // Calibration: the robotic SDK knows whether the device has been; the haptic SDK alone cannot tell.
  if (!l.calibrated) {
    if (!p.boolean("calibrate")) {
      close_device();
      throw std::runtime_error("the " + system +
                               " is not calibrated (the SDK: device not ready); calibrate it with the vendor's "
                               "tool, or set calibrate: true to have the SDK calibrate it (the handle moves)");
    }
    l.once = [&l] {
      l.sdk.calling("drdOpenID");
      l.calibrated = false;
      if (l.dhd->drd_open_id(l.id) < 0) {
        l.once_error = vendor_text(l.dhd->last_error());
        return;
      }
      l.sdk.calling("drdAutoInit");
      if (l.dhd->drd_auto_init(l.id) < 0) {
        l.once_error = vendor_text(l.dhd->last_error());
        return;
      }
      l.calibrated = true;
      l.sdk.calling("drdStop");
      if (l.dhd->drd_stop != nullptr) (void)l.dhd->drd_stop(true, l.id);
    };
    run_once("drdAutoInit", "calibration_timeout_s", p.real("calibration_timeout_s"));
    if (!l.calibrated) {
      close_device();
      throw std::runtime_error("the " + system + " could not be calibrated: " + l.once_error);
    }
  }
  l.device_gravity = p.string("gravity_compensation") == "device";

  DeviceDescription& d = description_;
  d.model = "forcedimension " + system;
  if (l.serial_number >= 0) d.serial = std::to_string(l.serial_number);
  d.vendor_software =
      "Force Dimension SDK" +
      (l.sdk_version[0] >= 0 ? " " + std::to_string(l.sdk_version[0]) + "." + std::to_string(l.sdk_version[1]) + "." +
                                   std::to_string(l.sdk_version[2])
                             : std::string(" (version not reported)")) +
      ", " + l.library->file();
  d.interface = DeviceInterface::handle;
  HandleDescription& h = d.handle;
  h.senses_orientation = m->orientation;
  h.actuated_torque = m->torque;
  h.has_gripper = m->gripper && l.has_gripper;
  h.actuated_gripper = h.has_gripper;
  h.buttons = 1;
  h.workspace_min = Eigen::Vector3d(-m->half_x, -m->half_yz, -m->half_yz);
  h.workspace_max = -h.workspace_min;
  const auto lowered = [&](const char* key, double nominal) {
    const double asked = p.real(key);
    if (asked > nominal && nominal > 0.0)
      throw ParameterError(key, "above the " + system + "'s nominal " + std::to_string(nominal));
    return asked > 0.0 ? asked : nominal;
  };
  h.max_force_n = lowered("max_force_n", m->force_n);
  h.max_torque_nm = lowered("max_torque_nm", m->torque_nm);
  h.max_gripper_force_n = lowered("max_gripper_force_n", m->gripper_n);
  h.recommended_stiffness_n_per_m = m->stiffness;
  h.recommended_damping_n_s_per_m = m->damping;
  h.recommended_rotational_stiffness_nm_per_rad = m->rotational_stiffness;
  h.recommended_rotational_damping_nm_s_per_rad = m->rotational_damping;
  d.capabilities.brakes = true;
  l.orientation = h.senses_orientation;
  l.gripper = h.has_gripper;
}

const char* ForceDimensionDevice::failure(const char* reason) noexcept { return failure_text_.keep(reason); }

const char* ForceDimensionDevice::stuck() noexcept {
  char reason[256];
  const SdkThread& sdk = link_->sdk;
  const double ms = static_cast<double>(realtime::TickSignal::now_ns() - sdk.stuck_since_ns()) * 1e-6;
  if (sdk.stuck_in()[0] != '\0')
    std::snprintf(reason, sizeof reason,
                  "the Force Dimension SDK has not returned from %s in %.0f ms (call_deadline_ms)", sdk.stuck_in(), ms);
  else  // between calls: the thread itself was not run in time
    std::snprintf(reason, sizeof reason,
                  "the thread that calls the Force Dimension SDK did not run within call_deadline_ms (%.0f ms): the "
                  "machine is overloaded",
                  static_cast<double>(deadline_ns_) * 1e-6);
  return failure(reason);
}

Outcome ForceDimensionDevice::reported() noexcept {
  if (!link_->failed) return Outcome::success();
  link_->failed = false;  // told once
  return Outcome::failure(failure(link_->error.data()));
}

Outcome ForceDimensionDevice::run_job(const SdkThread::Job& job, std::int64_t next_post_ns) noexcept {
  SdkThread& sdk = link_->sdk;
  // The previous job has returned (one stuck past its deadline: the fault), and its failure has been told.
  if (!sdk.wait(posted_ns_ + deadline_ns_)) return Outcome::failure(stuck());
  if (Outcome previous = reported(); !previous.ok()) return previous;
  posted_ns_ = realtime::TickSignal::now_ns();
  if (!sdk.post(job, next_post_ns) || !sdk.wait(posted_ns_ + deadline_ns_)) return Outcome::failure(stuck());
  return reported();
}

Outcome ForceDimensionDevice::enable() {
  if (!link_ || !link_->open) return Outcome::failure("the Force Dimension device is not open");
  failure_text_.clear();
  gripper_read_ = false;
  link_->failed = false;
  if (!link_->sdk.run(link_->enable_job, 1.0)) return Outcome::failure(stuck());
  return reported();
}

Outcome ForceDimensionDevice::read(const CycleTime& cycle, DeviceState& state) {
  read_ns_ = realtime::TickSignal::now_ns();
  if (Outcome done = run_job(link_->read_job); !done.ok()) return done;
  const DhdReading& r = link_->reading;
  HandleState& h = state.handle;
  state.timestamp_ns = cycle.time_ns;
  h.pose.position = Eigen::Vector3d(r.position[0], r.position[1], r.position[2]);
  h.twist.linear = Eigen::Vector3d(r.velocity[0], r.velocity[1], r.velocity[2]);
  if (description_.handle.senses_orientation) {
    Eigen::Matrix3d m;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m(i, j) = r.frame[i][j];
    h.pose.orientation = Eigen::Quaterniond(m);
    h.twist.angular = Eigen::Vector3d(r.angular_velocity[0], r.angular_velocity[1], r.angular_velocity[2]);
  }
  h.buttons = r.buttons;
  if (description_.handle.has_gripper) {
    const double before = h.gripper;
    h.gripper = r.gripper_rad;
    // The first sample has nothing to differentiate against: rate zero, not a jump from zero.
    h.gripper_rate = gripper_read_ && cycle.period_ns > 0
                         ? (h.gripper - before) / (static_cast<double>(cycle.period_ns) * 1e-9)
                         : 0.0;
    gripper_read_ = true;
  }
  return Outcome::success();
}

Outcome ForceDimensionDevice::write_handle(const CycleTime&, const HandleCommand& c) {
  std::array<double, 7>& f = link_->force;
  if (link_->sdk.busy()) return Outcome::failure(stuck());  // the job's input is the SDK thread's until it returns
  // Force, torque and gripper force (zero where the unit has no such actuator: HandleCommand's rule).
  f = {c.force_n.x(),   c.force_n.y(),   c.force_n.z(),    c.torque_nm.x(),
       c.torque_nm.y(), c.torque_nm.z(), c.gripper_force_n};
  // The next cycle's reads are expected one period after this cycle's.
  return run_job(link_->write_job, read_ns_ + period_ns_);
}

Outcome ForceDimensionDevice::brake(bool on) {
  link_->brakes_on = on;
  return run_job(link_->brake_job);
}

Outcome ForceDimensionDevice::reset_fault() {
  if (link_->sdk.busy()) return Outcome::failure(stuck());  // the SDK has not come back: nothing to recover to
  failure_text_.new_episode();                              // the next failure says its own reason
  return Outcome::success();
}

void ForceDimensionDevice::disable() { close_device(); }

void ForceDimensionDevice::close_device() noexcept {
  if (!link_ || !link_->open) return;
  // Zero force, forces off, brakes on, closed: on the SDK's thread, 0.5 s at most (a device that does not answer
  // is left to its own watchdog; its fault has said so).
  if (!link_->sdk.wait(realtime::TickSignal::now_ns() + 500'000'000)) return;
  (void)link_->sdk.run(link_->close_job, 0.5);
}

}  // namespace hapticd::plugins::forcedimension
