// A stand-in for 3D Systems' OpenHaptics HD library (libHD), built by the project for its tests: the C functions
// the openhaptics plugin loads, with the prototypes and constant values of the vendor's published headers (hd.h,
// hdDefines.h, hdScheduler.h of OpenHaptics 3.x). Nothing of the vendor's is copied or shipped; a real
// installation's libHD.so is found first when the session points at it.
//
// Behind the functions: up to 4 devices, each a stylus with mass and damping in a box-shaped workspace with stiff
// walls and a simulated hand pushing it; and the servo scheduler: one thread that, at the rate set, steps every
// device's physics under the force of its last frame and calls every scheduled callback (highest priority first),
// as the vendor's does. A control interface for the tests (standin_hd_*): the devices (from the variable
// HAPTICD_HD_STANDIN, "Default Device=Touch:220-10001,Right=Touch X:330-10002", a name's trailing "!update" or
// "!manual" for a calibration it needs), the hand (HAPTICD_HD_STANDIN_HAND "fx,fy,fz" and
// HAPTICD_HD_STANDIN_BUTTONS for a run of the server), a pause of the scheduler (a device that stops calling), an
// error in the next frame, a device unplugged, the linkage's angles, a PHANTOM Premium 6DOF with torque output, the
// last force written, the number of ticks, an hdInitDevice that hangs (standin_hd_hang_init, or
// HAPTICD_HD_STANDIN_HANG=init for a run of the server; 60 s at most) and a log of the lifecycle calls.
#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "hand_trigger.hpp"

#define STANDIN_API extern "C" __attribute__((visibility("default")))

namespace {

using HHD = unsigned int;
using HDenum = unsigned int;
using HDerror = unsigned int;
using HDCallbackCode = unsigned int;
using HDSchedulerCallback = HDCallbackCode (*)(void*);
struct HDErrorInfo {
  HDerror errorCode;
  int internalErrorCode;
  HHD hHD;
};

// hdDefines.h
constexpr HDerror kSuccess = 0x0000, kInvalidEnum = 0x0100, kInvalidValue = 0x0101, kInvalidOperation = 0x0102,
                  kBadHandle = 0x0104, kExceededMaxForce = 0x0201, kDeviceFault = 0x0300, kCommError = 0x0302,
                  kIllegalBegin = 0x0400, kIllegalEnd = 0x0401, kInvalidPriority = 0x0500;
constexpr HHD kInvalidHandle = 0xFFFFFFFF;
constexpr HDenum kCurrentButtons = 0x2000, kCurrentPosition = 0x2050, kCurrentVelocity = 0x2051,
                 kCurrentTransform = 0x2052, kCurrentAngularVelocity = 0x2053, kDeviceModelType = 0x2501,
                 kVersion = 0x2500, kDeviceDriverVersion = 0x2502, kDeviceVendor = 0x2503, kDeviceSerialNumber = 0x2504,
                 kUsableWorkspaceDimensions = 0x2551, kInputDof = 0x2553, kOutputDof = 0x2554,
                 kCalibrationStyle = 0x2555, kUpdateRate = 0x2600, kNominalMaxStiffness = 0x2602,
                 kNominalMaxForce = 0x2603, kNominalMaxContinuousForce = 0x2604, kNominalMaxDamping = 0x2609,
                 kNominalMaxTorqueForce = 0x2622, kCurrentForce = 0x2700, kCurrentTorque = 0x2701,
                 kCurrentJointAngles = 0x2100, kCurrentGimbalAngles = 0x2150, kForceOutput = 0x4000;
constexpr HDenum kCalibrationOk = 0x5000, kCalibrationNeedsUpdate = 0x5001, kCalibrationNeedsManualInput = 0x5002;
constexpr int kCalibrationEncoderReset = 1 << 0, kCalibrationInkwell = 1 << 2;
constexpr HDCallbackCode kCallbackDone = 0;

struct Device {
  std::string name = "Default Device", model = "Touch", serial = "220-10001";
  HDenum calibration = kCalibrationOk;
  bool open = false, force_output = false, in_frame = false, unplugged = false;
  bool torque_output = false;  // a PHANTOM Premium 6DOF: torques in mN m (HD_CURRENT_TORQUE)
  double max_torque_mnm = 0.0;
  double mass_kg = 0.045, damping = 0.4, wall_stiffness = 2000.0, max_force_n = 3.3;
  std::array<double, 3> lo{-0.08, -0.06, -0.035}, hi{0.08, 0.06, 0.035};  // m (the Touch's usable box)
  std::array<double, 3> p{0, 0, 0}, v{0, 0, 0}, f{0, 0, 0}, hand{0, 0, 0};
  std::array<double, 3> t{0, 0, 0};                                // the torque last written [mN m]
  std::array<double, 6> linkage{0.1, 0.2, 0.3, -0.4, -0.5, -0.6};  // joint, then gimbal angles [rad]
  int buttons = 0;
  HDerror fail_next_frame = kSuccess;
};

struct Callback {
  unsigned long id;
  HDSchedulerCallback function;
  void* data;
  unsigned short priority;
  bool active;
};

std::recursive_mutex mutex;  // the API's state; the scheduler thread holds it while it calls back
std::vector<Device> devices;
bool set_up = false;
thread_local int current = -1;    // the current device is the calling thread's
std::vector<HDErrorInfo> errors;  // the error stack hdGetError pops
std::vector<Callback> callbacks;
unsigned long next_callback = 1;
unsigned long rate_hz = 1000;
std::thread scheduler;
std::atomic<bool> scheduler_running{false};
std::atomic<bool> hang_init{false};  // hdInitDevice hangs while set
std::atomic<std::int64_t> pause_until_ns{0};
std::atomic<std::uint64_t> ticks{0};
std::string call_log;  // the lifecycle calls, in order (not the per-frame ones)

void log_call(const char* name, int argument = -1) {
  call_log += name;
  call_log += argument >= 0 ? "(" + std::to_string(argument) + ")\n" : std::string("\n");
}

std::int64_t now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

void raise(HDerror code, int internal = 0) {
  errors.push_back(HDErrorInfo{code, internal, current < 0 ? kInvalidHandle : static_cast<HHD>(current)});
}

void setup_from(const char* spec) {
  devices.clear();
  std::string s = spec != nullptr ? spec : "Default Device=Touch:220-10001";
  std::size_t start = 0;
  while (start <= s.size()) {
    const std::size_t comma = std::min(s.find(',', start), s.size());
    const std::string item = s.substr(start, comma - start);
    if (!item.empty() && devices.size() < 4) {
      Device d;
      std::string rest = item;
      if (const std::size_t eq = rest.find('='); eq != std::string::npos) {
        d.name = rest.substr(0, eq);
        rest = rest.substr(eq + 1);
      }
      if (const std::size_t bang = rest.find('!'); bang != std::string::npos) {
        d.calibration = rest.substr(bang + 1) == "manual" ? kCalibrationNeedsManualInput : kCalibrationNeedsUpdate;
        rest = rest.substr(0, bang);
      }
      const std::size_t colon = rest.find(':');
      d.model = rest.substr(0, colon);
      if (colon != std::string::npos) d.serial = rest.substr(colon + 1);
      if (d.model == "PHANTOM Premium 6DOF") {
        d.torque_output = true;
        d.max_torque_mnm = 170.0;
        d.max_force_n = 8.5;
      }
      if (d.model == "Touch X") {
        d.max_force_n = 7.9;
        d.lo = {-0.08, -0.06, -0.05};
        d.hi = {0.08, 0.06, 0.05};
      }
      devices.push_back(d);
    }
    start = comma + 1;
  }
  // A run of the server has no test to push or press: the hand's force "fx,fy,fz" (N) and the buttons held, on
  // every device.
  if (std::array<double, 3> f{}; hapticd::standins::hand_from_environment("HAPTICD_HD_STANDIN_HAND", f))
    for (Device& d : devices) d.hand = f;
  if (const char* held = std::getenv("HAPTICD_HD_STANDIN_BUTTONS"); held != nullptr)
    for (Device& d : devices) d.buttons = static_cast<int>(std::strtol(held, nullptr, 0));
  set_up = true;
}

Device* current_device() {
  if (current < 0 || current >= static_cast<int>(devices.size()) || !devices[static_cast<std::size_t>(current)].open) {
    raise(kBadHandle);
    return nullptr;
  }
  return &devices[static_cast<std::size_t>(current)];
}

hapticd::standins::HandTrigger hand_trigger;

// A hand that pushes holds the stylus: its arm's mass and damping move with it (a person's hand, not a force from
// nowhere - 1.5 N on the bare 45 g stylus flung it to 0.95 m/s in 32 ms, past the Touch's speed limit).
constexpr double kArmMassKg = 0.3, kArmDamping = 4.0;

// The stylus under the last frame's force, the hand and the walls, over dt (semi-implicit Euler).
void step(Device& d, double dt) {
  const bool pushing = hand_trigger.pushing() && (d.hand[0] != 0.0 || d.hand[1] != 0.0 || d.hand[2] != 0.0);
  const double mass = d.mass_kg + (pushing ? kArmMassKg : 0.0);
  const double damping = d.damping + (pushing ? kArmDamping : 0.0);
  for (std::size_t i = 0; i < 3; ++i) {
    double wall = 0.0;
    if (d.p[i] > d.hi[i]) wall = -d.wall_stiffness * (d.p[i] - d.hi[i]);
    if (d.p[i] < d.lo[i]) wall = -d.wall_stiffness * (d.p[i] - d.lo[i]);
    const double applied = d.force_output ? d.f[i] : 0.0;
    const double a = (applied + (pushing ? d.hand[i] : 0.0) + wall - damping * d.v[i]) / mass;
    d.v[i] += a * dt;
    d.p[i] += d.v[i] * dt;
  }
}

void run_scheduler() {
  std::int64_t next = now_ns();
  while (scheduler_running.load()) {
    const std::int64_t period = 1'000'000'000 / static_cast<std::int64_t>(std::max(1ul, rate_hz));
    next += period;
    timespec ts{static_cast<time_t>(next / 1'000'000'000), static_cast<long>(next % 1'000'000'000)};
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
    if (now_ns() < pause_until_ns.load()) continue;  // the device stopped calling
    std::vector<Callback> due;
    {
      std::lock_guard lock(mutex);
      for (Device& d : devices)
        if (d.open) step(d, static_cast<double>(period) * 1e-9);
      for (const Callback& c : callbacks)
        if (c.active) due.push_back(c);
    }
    std::stable_sort(due.begin(), due.end(),
                     [](const Callback& a, const Callback& b) { return a.priority > b.priority; });
    ticks.fetch_add(1);
    for (const Callback& c : due)
      if (c.function(c.data) == kCallbackDone) {
        std::lock_guard lock(mutex);
        for (Callback& k : callbacks)
          if (k.id == c.id) k.active = false;
      }
  }
}

}  // namespace

// ---- the vendor's functions (hd.h, hdScheduler.h) ----

STANDIN_API HHD hdInitDevice(const char* name) {
  if (const char* hang = std::getenv("HAPTICD_HD_STANDIN_HANG"); hang != nullptr && std::string(hang) == "init")
    hang_init.store(true);
  // Hangs outside the mutex, as a call stuck in the driver would: the tests' controls still answer.
  for (int ms = 0; hang_init.load() && ms < 60000; ++ms) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  std::lock_guard lock(mutex);
  if (!set_up) setup_from(std::getenv("HAPTICD_HD_STANDIN"));
  for (std::size_t i = 0; i < devices.size(); ++i) {
    Device& d = devices[i];
    if (name == nullptr ? i == 0 : d.name == name) {
      if (d.open) {
        raise(0x0301);  // HD_DEVICE_ALREADY_INITIATED
        return kInvalidHandle;
      }
      d.open = true;
      d.force_output = false;
      log_call("hdInitDevice", static_cast<int>(i));
      d.p = d.v = d.f = {0, 0, 0};
      current = static_cast<int>(i);
      return static_cast<HHD>(i);
    }
  }
  raise(kCommError, -1);  // the vendor's answer when no device of that name answers
  return kInvalidHandle;
}
STANDIN_API void hdDisableDevice(HHD h) {
  std::lock_guard lock(mutex);
  if (h >= devices.size()) return raise(kBadHandle);
  log_call("hdDisableDevice", static_cast<int>(h));
  devices[h].open = false;
  devices[h].force_output = false;
  devices[h].f = {0, 0, 0};
}
STANDIN_API void hdMakeCurrentDevice(HHD h) {
  std::lock_guard lock(mutex);
  if (h >= devices.size() || !devices[h].open) return raise(kBadHandle);
  current = static_cast<int>(h);
}
STANDIN_API HHD hdGetCurrentDevice() {
  std::lock_guard lock(mutex);
  return current < 0 ? kInvalidHandle : static_cast<HHD>(current);
}
STANDIN_API void hdBeginFrame(HHD h) {
  std::lock_guard lock(mutex);
  if (h >= devices.size() || !devices[h].open) return raise(kBadHandle);
  if (devices[h].in_frame) return raise(kIllegalBegin);
  devices[h].in_frame = true;
  current = static_cast<int>(h);
  if (devices[h].unplugged) {  // two errors on the stack: the device's fault, then the communication's
    raise(kDeviceFault);
    raise(kCommError, -28);
  }
}
STANDIN_API void hdEndFrame(HHD h) {
  std::lock_guard lock(mutex);
  if (h >= devices.size() || !devices[h].in_frame) return raise(kIllegalEnd);
  Device& d = devices[h];
  d.in_frame = false;
  if (d.fail_next_frame != kSuccess) {
    raise(d.fail_next_frame, 42);
    d.fail_next_frame = kSuccess;
  }
}
STANDIN_API void hdGetIntegerv(HDenum what, int* out) {
  std::lock_guard lock(mutex);
  Device* d = current_device();
  if (d == nullptr) return;
  switch (what) {
    case kCurrentButtons:
      *out = d->buttons;
      return;
    case kInputDof:
      *out = 6;
      return;
    case kOutputDof:
      *out = d->torque_output ? 6 : 3;
      return;
    case kCalibrationStyle:
      *out = kCalibrationEncoderReset | kCalibrationInkwell;
      return;
    case kUpdateRate:
      *out = static_cast<int>(rate_hz);
      return;
    default:
      raise(kInvalidEnum);
  }
}
STANDIN_API void hdGetDoublev(HDenum what, double* out) {
  std::lock_guard lock(mutex);
  Device* d = current_device();
  if (d == nullptr) return;
  switch (what) {
    case kCurrentPosition:
      for (std::size_t i = 0; i < 3; ++i) out[i] = d->p[i] * 1e3;
      return;
    case kCurrentVelocity:
      for (std::size_t i = 0; i < 3; ++i) out[i] = d->v[i] * 1e3;
      return;
    case kCurrentTransform:  // the stylus upright (no rotation), translation in mm; column-major
      for (int i = 0; i < 16; ++i) out[i] = (i % 5 == 0) ? 1.0 : 0.0;
      for (std::size_t i = 0; i < 3; ++i) out[12 + i] = d->p[i] * 1e3;
      return;
    case kCurrentAngularVelocity:
      out[0] = out[1] = out[2] = 0.0;
      return;
    case kUsableWorkspaceDimensions:
      for (std::size_t i = 0; i < 3; ++i) {
        out[i] = d->lo[i] * 1e3;
        out[3 + i] = d->hi[i] * 1e3;
      }
      return;
    case kNominalMaxForce:
      *out = d->max_force_n;
      return;
    case kNominalMaxContinuousForce:
      *out = d->max_force_n * 0.27;
      return;
    case kNominalMaxStiffness:  // N/mm
      *out = d->model == "Touch X" ? 1.86 : 1.26;
      return;
    case kNominalMaxDamping:  // N s/mm
      *out = 0.005;
      return;
    case kCurrentForce:
      for (std::size_t i = 0; i < 3; ++i) out[i] = d->f[i];
      return;
    case kCurrentJointAngles:
      for (std::size_t i = 0; i < 3; ++i) out[i] = d->linkage[i];
      return;
    case kCurrentGimbalAngles:
      for (std::size_t i = 0; i < 3; ++i) out[i] = d->linkage[3 + i];
      return;
    case kNominalMaxTorqueForce:
      if (!d->torque_output) return raise(kInvalidEnum);
      *out = d->max_torque_mnm;
      return;
    // HD_NOMINAL_MAX_TORQUE_STIFFNESS and _DAMPING are not reported (two errors on the stack, as a device that
    // lacks a figure leaves them): the plugin must not take them for a frame's errors.
    default:
      raise(kInvalidEnum);
  }
}
STANDIN_API const char* hdGetString(HDenum what) {
  std::lock_guard lock(mutex);
  Device* d = current_device();
  if (d == nullptr) return nullptr;
  switch (what) {
    case kDeviceModelType:
      return d->model.c_str();
    case kDeviceSerialNumber:
      return d->serial.c_str();
    case kDeviceVendor:
      return "project stand-in";
    case kVersion:
      return "3.4 (hapticd's stand-in)";
    case kDeviceDriverVersion:
      return "none (hapticd's stand-in)";
    default:
      raise(kInvalidEnum);
      return nullptr;
  }
}
STANDIN_API void hdSetDoublev(HDenum what, const double* in) {
  std::lock_guard lock(mutex);
  Device* d = current_device();
  if (d == nullptr) return;
  if (what != kCurrentForce && !(what == kCurrentTorque && d->torque_output)) return raise(kInvalidEnum);
  if (!d->in_frame) return raise(kInvalidOperation);  // forces are set inside a frame
  if (d->unplugged) return;
  if (what == kCurrentTorque) {
    for (std::size_t i = 0; i < 3; ++i) d->t[i] = std::clamp(in[i], -d->max_torque_mnm, d->max_torque_mnm);
    return;
  }
  for (std::size_t i = 0; i < 3; ++i) {
    d->f[i] = std::clamp(in[i], -d->max_force_n, d->max_force_n);
    if (std::abs(in[i]) > d->max_force_n) raise(kExceededMaxForce);
  }
}
STANDIN_API void hdEnable(HDenum what) {
  std::lock_guard lock(mutex);
  Device* d = current_device();
  if (d == nullptr) return;
  if (what != kForceOutput) return raise(kInvalidEnum);
  log_call("hdEnable(HD_FORCE_OUTPUT)", current);
  d->force_output = true;
}
STANDIN_API void hdDisable(HDenum what) {
  std::lock_guard lock(mutex);
  Device* d = current_device();
  if (d == nullptr) return;
  if (what != kForceOutput) return raise(kInvalidEnum);
  log_call("hdDisable(HD_FORCE_OUTPUT)", current);
  d->force_output = false;
}
STANDIN_API unsigned char hdIsEnabled(HDenum what) {
  std::lock_guard lock(mutex);
  Device* d = current_device();
  return d != nullptr && what == kForceOutput && d->force_output ? 1 : 0;
}
STANDIN_API HDErrorInfo hdGetError() {
  std::lock_guard lock(mutex);
  if (errors.empty()) return HDErrorInfo{kSuccess, 0, kInvalidHandle};
  const HDErrorInfo e = errors.back();
  errors.pop_back();
  return e;
}
STANDIN_API const char* hdGetErrorString(HDerror code) {
  switch (code) {
    case kSuccess:
      return "no error";
    case kInvalidEnum:
      return "invalid enumeration";
    case kInvalidValue:
      return "invalid value";
    case kInvalidOperation:
      return "invalid operation";
    case kBadHandle:
      return "bad device handle";
    case kExceededMaxForce:
      return "the force exceeded the device's maximum";
    case kDeviceFault:
      return "device fault";
    case kCommError:
      return "communication error (device not found or not answering)";
    case kIllegalBegin:
      return "hdBeginFrame inside a frame";
    case kIllegalEnd:
      return "hdEndFrame without a frame";
    case kInvalidPriority:
      return "invalid scheduler priority";
    default:
      return nullptr;
  }
}
STANDIN_API HDenum hdCheckCalibration() {
  std::lock_guard lock(mutex);
  Device* d = current_device();
  log_call("hdCheckCalibration", current);
  return d == nullptr ? kCalibrationOk : d->calibration;
}
STANDIN_API void hdUpdateCalibration(HDenum style) {
  std::lock_guard lock(mutex);
  Device* d = current_device();
  if (d == nullptr) return;
  if (style != kCalibrationEncoderReset && style != kCalibrationInkwell) return raise(kInvalidValue);
  if (d->calibration == kCalibrationNeedsUpdate) d->calibration = kCalibrationOk;
}
STANDIN_API void hdSetSchedulerRate(unsigned long rate) {
  std::lock_guard lock(mutex);
  if (rate != 500 && rate != 1000 && rate != 2000) return raise(kInvalidValue);
  rate_hz = rate;
}
STANDIN_API void hdStartScheduler() {
  std::lock_guard lock(mutex);
  if (scheduler_running.exchange(true)) return raise(kInvalidOperation);
  log_call("hdStartScheduler");
  scheduler = std::thread(run_scheduler);
}
STANDIN_API void hdStopScheduler() {
  {
    std::lock_guard lock(mutex);
    if (!scheduler_running.exchange(false)) return raise(kInvalidOperation);
    log_call("hdStopScheduler");
  }
  if (scheduler.joinable()) scheduler.join();
}
STANDIN_API unsigned long hdScheduleAsynchronous(HDSchedulerCallback function, void* data, unsigned short priority) {
  std::lock_guard lock(mutex);
  callbacks.push_back(Callback{next_callback, function, data, priority, true});
  log_call("hdScheduleAsynchronous");
  return next_callback++;
}
STANDIN_API void hdUnschedule(unsigned long id) {
  std::lock_guard lock(mutex);
  log_call("hdUnschedule");
  for (Callback& c : callbacks)
    if (c.id == id) c.active = false;
}

// ---- the tests' controls ----

// The hand on device `index` pushes with this force [N]; these buttons are held.
STANDIN_API void standin_hd_hand(int index, double fx, double fy, double fz, int buttons) {
  std::lock_guard lock(mutex);
  if (!set_up) setup_from(std::getenv("HAPTICD_HD_STANDIN"));
  if (index < 0 || index >= static_cast<int>(devices.size())) return;
  devices[static_cast<std::size_t>(index)].hand = {fx, fy, fz};
  devices[static_cast<std::size_t>(index)].buttons = buttons;
}
// hdInitDevice hangs (true) until released (false).
STANDIN_API void standin_hd_hang_init(bool hang) { hang_init.store(hang); }
// The scheduler calls no callback for this long (a device that stops calling back).
STANDIN_API void standin_hd_pause(double seconds) {
  pause_until_ns.store(now_ns() + static_cast<std::int64_t>(seconds * 1e9));
}
// The next frame of device `index` ends with this HD error.
STANDIN_API void standin_hd_fail_next_frame(int index, unsigned int code) {
  std::lock_guard lock(mutex);
  if (index >= 0 && index < static_cast<int>(devices.size()))
    devices[static_cast<std::size_t>(index)].fail_next_frame = code;
}
// Device `index` is unplugged (true: every frame then fails with a communication error and a device fault, and no
// force reaches it) or plugged in again.
STANDIN_API void standin_hd_unplug(int index, bool unplugged) {
  std::lock_guard lock(mutex);
  if (index >= 0 && index < static_cast<int>(devices.size()))
    devices[static_cast<std::size_t>(index)].unplugged = unplugged;
}
// The linkage's angles of device `index`: three joint angles, then three gimbal angles [rad].
STANDIN_API void standin_hd_linkage(int index, const double* angles) {
  std::lock_guard lock(mutex);
  if (index >= 0 && index < static_cast<int>(devices.size()))
    for (std::size_t i = 0; i < 6; ++i) devices[static_cast<std::size_t>(index)].linkage[i] = angles[i];
}
// The torque last written to device `index` [mN m] (a PHANTOM Premium 6DOF).
STANDIN_API void standin_hd_torque(int index, double* torque) {
  std::lock_guard lock(mutex);
  if (index >= 0 && index < static_cast<int>(devices.size()))
    for (std::size_t i = 0; i < 3; ++i) torque[i] = devices[static_cast<std::size_t>(index)].t[i];
}
// The stylus's position [m] and the force last written [N] of device `index`.
STANDIN_API void standin_hd_state(int index, double* position, double* force) {
  std::lock_guard lock(mutex);
  if (index < 0 || index >= static_cast<int>(devices.size())) return;
  for (std::size_t i = 0; i < 3; ++i) {
    position[i] = devices[static_cast<std::size_t>(index)].p[i];
    force[i] = devices[static_cast<std::size_t>(index)].f[i];
  }
}
STANDIN_API unsigned long long standin_hd_ticks() { return ticks.load(); }
// Forget every device (the next call reads HAPTICD_HD_STANDIN again, or this spec when given).
STANDIN_API void standin_hd_setup(const char* spec) {
  std::lock_guard lock(mutex);
  setup_from(spec != nullptr ? spec : std::getenv("HAPTICD_HD_STANDIN"));
  errors.clear();
  callbacks.clear();
  pause_until_ns.store(0);
  call_log.clear();
}
// The lifecycle calls so far, one per line ("hdInitDevice(0)", "hdCheckCalibration(0)", ...).
STANDIN_API const char* standin_hd_call_log() {
  std::lock_guard lock(mutex);
  static std::string copy;
  copy = call_log;
  return copy.c_str();
}
