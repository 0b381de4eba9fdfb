// A stand-in for Force Dimension's SDK library (libdhd / libdrd), built by the project for its tests: the C
// functions the forcedimension plugin loads, with the prototypes of the vendor's published C header (dhdc.h and
// drdc.h of SDK 3.x; checked against the header of SDK 3.6.0 as published: every function takes the device ID as
// its last argument, `char`, -1 meaning the default device - the last one opened). Nothing of the vendor's is
// copied or shipped; a real installation's libdrd.so is found first when the session points at it.
//
// Behind the functions: up to 4 devices, each a handle with mass and damping in a box-shaped workspace with stiff
// walls, a simulated hand pushing it with a constant force, buttons and a gripper; and a control interface for the
// tests (standin_dhd_*): the devices (from the variable HAPTICD_DHD_STANDIN, "omega.6:10001,omega.7:10002", or
// standin_dhd_setup), a fixed physics step (lockstep: standin_dhd_set_step or HAPTICD_DHD_STANDIN_STEP) or the
// wall clock, buttons held and the hand's push (standin_dhd_hand, or HAPTICD_DHD_STANDIN_BUTTONS and
// HAPTICD_DHD_STANDIN_HAND "fx,fy,fz" for a run of the server), faults on cue (unplugged, one failing
// force call, uncalibrated, a call that hangs: "hang_open", "hang_position", "hang_force" until "release" - or
// HAPTICD_DHD_STANDIN_HANG=open|position|force for a run of the server; a hung call returns after 60 s at most),
// and a log of the lifecycle calls.
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "hand_trigger.hpp"

#define STANDIN_API extern "C" __attribute__((visibility("default")))

namespace {

// The error codes of dhd_errors, in the header's order (only those the stand-in raises are named).
enum : int {
  kNoError = 0,
  kError = 1,
  kErrorCom = 2,
  kErrorNoDeviceFound = 5,
  kErrorNotAvailable = 6,
  kErrorDeviceNotReady = 12,
  kErrorInvalidIndex = 15,
};
constexpr int kMotorSaturated = 2;  // DHD_MOTOR_SATURATED: a positive, non-error return
constexpr int kMaxStatus = 15;      // DHD_MAX_STATUS
constexpr int kStatusPower = 0, kStatusConnected = 1, kStatusForce = 5, kStatusBrake = 6, kStatusGravity = 10;

struct Device {
  std::string type_name = "omega.6";
  int system_type = 35;  // DHD_DEVICE_OMEGA331
  int serial = 10001;
  bool open = false, force_on = false, brakes = true, gravity = false, calibrated = true;
  bool unplugged = false, fail_next_force = false, has_gripper = false;
  double mass_kg = 0.25, damping = 2.0, wall_stiffness = 4000.0, half_extent_m = 0.07, max_force_n = 12.0;
  std::array<double, 3> p{0, 0, 0}, v{0, 0, 0}, f{0, 0, 0}, t{0, 0, 0}, hand{0, 0, 0};
  double gripper_rad = 0.3, gripper_force = 0.0;
  unsigned buttons = 0;
  std::chrono::steady_clock::time_point last{};
  bool stepped = false;
};

std::mutex mutex;  // the plugin's loop and a test's control calls

// A call that hangs on cue, as one stuck in a USB transfer would (outside the mutex: the tests' controls still
// answer). 0: none; else the call's number below.
enum Hang : int { kHangNone = 0, kHangOpen = 1, kHangPosition = 2, kHangForce = 3 };
std::atomic<int> hang_call{-1};  // -1: not read from the environment yet
std::atomic<bool> released{false};
std::atomic<int> hang_device{-1};  // the device whose calls hang; -1: every device

int hang_of(const char* name) {
  if (name == nullptr) return kHangNone;
  if (std::strcmp(name, "open") == 0) return kHangOpen;
  if (std::strcmp(name, "position") == 0) return kHangPosition;
  if (std::strcmp(name, "force") == 0) return kHangForce;
  return kHangNone;
}

void maybe_hang(int call, int id = -1) {
  int h = hang_call.load();
  if (h < 0) {
    int expected = -1;
    (void)hang_call.compare_exchange_strong(expected, hang_of(std::getenv("HAPTICD_DHD_STANDIN_HANG")));
    h = hang_call.load();
  }
  if (h != call) return;
  if (const int only = hang_device.load(); only >= 0 && id >= 0 && id != only) return;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!released.load() && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
}
std::vector<Device> devices;
bool set_up = false;
int current = -1;  // the default device (ID -1): the last one opened
int last_error = kNoError;
double fixed_step_s = 0.0;  // > 0: each force call advances the physics by this much (lockstep)
std::string call_log;
std::string last_error_text;

const char* text_of(int error) {
  switch (error) {
    case kNoError:
      return "no error";
    case kErrorCom:
      return "communication error between the host and the device";
    case kErrorNoDeviceFound:
      return "no compatible Force Dimension device found";
    case kErrorNotAvailable:
      return "feature not available on this device";
    case kErrorDeviceNotReady:
      return "device not ready (not calibrated)";
    case kErrorInvalidIndex:
      return "invalid device index";
    default:
      return "undocumented error";
  }
}

int fail(int error) {
  last_error = error;
  return -1;
}

void log_call(const char* name, int id) {
  call_log += name;
  call_log += "(" + std::to_string(id) + ")\n";
}

void setup_from(const char* spec) {
  devices.clear();
  std::string s = spec != nullptr ? spec : "omega.6:10001";
  std::size_t start = 0;
  while (start <= s.size()) {
    const std::size_t comma = std::min(s.find(',', start), s.size());
    const std::string item = s.substr(start, comma - start);
    if (!item.empty() && devices.size() < 4) {
      Device d;
      const std::size_t colon = item.find(':');
      d.type_name = item.substr(0, colon);
      if (colon != std::string::npos) d.serial = std::atoi(item.c_str() + colon + 1);
      d.has_gripper = d.type_name == "omega.7" || d.type_name == "sigma.7" || d.type_name == "lambda.7";
      d.system_type = d.has_gripper ? 35 : 34;
      devices.push_back(d);
    }
    start = comma + 1;
  }
  set_up = true;
  current = -1;
  // Buttons held on every device from the start (a run of the server has no test to press them).
  if (const char* held = std::getenv("HAPTICD_DHD_STANDIN_BUTTONS"); held != nullptr)
    for (Device& d : devices) d.buttons = static_cast<unsigned>(std::strtoul(held, nullptr, 0));
  // A run of the server has no test to push either: the hand's force on every device, "fx,fy,fz" (N).
  if (std::array<double, 3> f{}; hapticd::standins::hand_from_environment("HAPTICD_DHD_STANDIN_HAND", f))
    for (Device& d : devices) d.hand = f;
  // A lockstep run of the server: each force call advances the physics by this much (seconds).
  if (const char* step = std::getenv("HAPTICD_DHD_STANDIN_STEP"); step != nullptr) fixed_step_s = std::atof(step);
}

// The device an ID names (-1: the default), or nullptr with the error set.
Device* device(char id) {
  if (!set_up) setup_from(std::getenv("HAPTICD_DHD_STANDIN"));
  const int index = id < 0 ? current : id;
  if (index < 0 || index >= static_cast<int>(devices.size()) || !devices[static_cast<std::size_t>(index)].open) {
    last_error = kErrorInvalidIndex;
    return nullptr;
  }
  Device& d = devices[static_cast<std::size_t>(index)];
  if (d.unplugged) {
    last_error = kErrorCom;
    return nullptr;
  }
  return &d;
}

hapticd::standins::HandTrigger hand_trigger;

// The handle's motion under the last force, the hand and the walls, over dt (semi-implicit Euler).
void step(Device& d, double dt) {
  const bool pushing = hand_trigger.pushing();
  for (int i = 0; i < 3; ++i) {
    double wall = 0.0;
    if (d.p[i] > d.half_extent_m) wall = -d.wall_stiffness * (d.p[i] - d.half_extent_m);
    if (d.p[i] < -d.half_extent_m) wall = -d.wall_stiffness * (d.p[i] + d.half_extent_m);
    const double applied = d.force_on ? d.f[i] : 0.0;
    const double a = (applied + (pushing ? d.hand[i] : 0.0) + wall - d.damping * d.v[i]) / d.mass_kg;
    d.v[i] = d.brakes ? 0.0 : d.v[i] + a * dt;
    d.p[i] += d.v[i] * dt;
  }
}

int open_index(int index) {
  if (index < 0 || index >= static_cast<int>(devices.size())) return fail(kErrorNoDeviceFound);
  Device& d = devices[static_cast<std::size_t>(index)];
  if (d.unplugged) return fail(kErrorNoDeviceFound);
  d.open = true;
  d.force_on = false;
  d.brakes = true;
  d.stepped = false;
  current = index;
  log_call("dhdOpen", index);
  return index;
}

}  // namespace

// ---- the vendor's functions (dhdc.h, drdc.h; SDK 3.x) ----

STANDIN_API int dhdErrorGetLast() { return last_error; }
STANDIN_API const char* dhdErrorGetLastStr() { return text_of(last_error); }
STANDIN_API const char* dhdErrorGetStr(int error) { return text_of(error); }
STANDIN_API void dhdGetSDKVersion(int* major, int* minor, int* release, int* revision) {
  *major = 3;
  *minor = 6;
  *release = 0;
  *revision = 0;
}
STANDIN_API int dhdGetDeviceCount() {
  std::lock_guard lock(mutex);
  if (!set_up) setup_from(std::getenv("HAPTICD_DHD_STANDIN"));
  int n = 0;
  for (const Device& d : devices) n += d.unplugged ? 0 : 1;
  return n;
}
STANDIN_API int dhdOpen() {
  std::lock_guard lock(mutex);
  if (!set_up) setup_from(std::getenv("HAPTICD_DHD_STANDIN"));
  for (std::size_t i = 0; i < devices.size(); ++i)
    if (!devices[i].open && !devices[i].unplugged) return open_index(static_cast<int>(i));
  return fail(kErrorNoDeviceFound);
}
STANDIN_API int dhdOpenID(char index) {
  maybe_hang(kHangOpen);
  std::lock_guard lock(mutex);
  if (!set_up) setup_from(std::getenv("HAPTICD_DHD_STANDIN"));
  return open_index(index);
}
STANDIN_API int dhdOpenSerial(int serial) {
  maybe_hang(kHangOpen);
  std::lock_guard lock(mutex);
  if (!set_up) setup_from(std::getenv("HAPTICD_DHD_STANDIN"));
  for (std::size_t i = 0; i < devices.size(); ++i)
    if (devices[i].serial == serial) return open_index(static_cast<int>(i));
  return fail(kErrorNoDeviceFound);
}
STANDIN_API int dhdClose(char id) {
  std::lock_guard lock(mutex);
  Device* d = device(id);
  if (d == nullptr) return -1;
  d->open = false;
  log_call("dhdClose", id);
  return 0;
}
STANDIN_API int dhdGetSerialNumber(unsigned short* sn, char id) {
  std::lock_guard lock(mutex);
  Device* d = device(id);
  if (d == nullptr) return -1;
  *sn = static_cast<unsigned short>(d->serial);
  return 0;
}
STANDIN_API int dhdGetSystemType(char id) {
  std::lock_guard lock(mutex);
  Device* d = device(id);
  return d == nullptr ? -1 : d->system_type;
}
STANDIN_API const char* dhdGetSystemName(char id) {
  std::lock_guard lock(mutex);
  Device* d = device(id);
  return d == nullptr ? nullptr : d->type_name.c_str();
}
STANDIN_API bool dhdHasGripper(char id) {
  std::lock_guard lock(mutex);
  Device* d = device(id);
  return d != nullptr && d->has_gripper;
}
STANDIN_API int dhdGetStatus(int status[kMaxStatus], char id) {
  std::lock_guard lock(mutex);
  Device* d = device(id);
  if (d == nullptr) return -1;
  std::fill(status, status + kMaxStatus, 0);
  status[kStatusPower] = 1;
  status[kStatusConnected] = 1;
  status[kStatusForce] = d->force_on ? 1 : 0;
  status[kStatusBrake] = d->brakes ? 1 : 0;
  status[kStatusGravity] = d->gravity ? 1 : 0;
  return 0;
}
STANDIN_API int dhdEnableForce(unsigned char on, char id) {
  std::lock_guard lock(mutex);
  Device* d = device(id);
  if (d == nullptr) return -1;
  if (on != 0 && !d->calibrated) return fail(kErrorDeviceNotReady);
  d->force_on = on != 0;
  d->brakes = on == 0;
  log_call(on != 0 ? "dhdEnableForce(on)" : "dhdEnableForce(off)", id);
  return 0;
}
STANDIN_API int dhdSetBrakes(int on, char id) {
  std::lock_guard lock(mutex);
  Device* d = device(id);
  if (d == nullptr) return -1;
  d->brakes = on != 0;
  if (d->brakes) d->v = {0, 0, 0};
  log_call(on != 0 ? "dhdSetBrakes(on)" : "dhdSetBrakes(off)", id);
  return 0;
}
STANDIN_API int dhdSetGravityCompensation(int on, char id) {
  std::lock_guard lock(mutex);
  Device* d = device(id);
  if (d == nullptr) return -1;
  d->gravity = on != 0;
  log_call(on != 0 ? "dhdSetGravityCompensation(on)" : "dhdSetGravityCompensation(off)", id);
  return 0;
}
STANDIN_API int dhdGetPosition(double* px, double* py, double* pz, char id) {
  maybe_hang(kHangPosition, id);
  std::lock_guard lock(mutex);
  Device* d = device(id);
  if (d == nullptr) return -1;
  *px = d->p[0];
  *py = d->p[1];
  *pz = d->p[2];
  return 0;
}
STANDIN_API int dhdGetLinearVelocity(double* vx, double* vy, double* vz, char id) {
  std::lock_guard lock(mutex);
  Device* d = device(id);
  if (d == nullptr) return -1;
  *vx = d->v[0];
  *vy = d->v[1];
  *vz = d->v[2];
  return 0;
}
STANDIN_API int dhdGetOrientationFrame(double matrix[3][3], char id) {
  std::lock_guard lock(mutex);
  if (device(id) == nullptr) return -1;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) matrix[r][c] = r == c ? 1.0 : 0.0;
  return 0;
}
STANDIN_API int dhdGetAngularVelocityRad(double* wx, double* wy, double* wz, char id) {
  std::lock_guard lock(mutex);
  if (device(id) == nullptr) return -1;
  *wx = *wy = *wz = 0.0;
  return 0;
}
STANDIN_API unsigned int dhdGetButtonMask(char id) {
  std::lock_guard lock(mutex);
  Device* d = device(id);
  return d == nullptr ? 0u : d->buttons;
}
STANDIN_API int dhdGetGripperAngleRad(double* a, char id) {
  std::lock_guard lock(mutex);
  Device* d = device(id);
  if (d == nullptr) return -1;
  if (!d->has_gripper) return fail(kErrorNotAvailable);
  *a = d->gripper_rad;
  return 0;
}
STANDIN_API int dhdSetForceAndTorqueAndGripperForce(double fx, double fy, double fz, double tx, double ty, double tz,
                                                    double fg, char id) {
  maybe_hang(kHangForce, id);
  std::lock_guard lock(mutex);
  Device* d = device(id);
  if (d == nullptr) return -1;
  if (d->fail_next_force) {
    d->fail_next_force = false;
    return fail(kErrorCom);
  }
  // The physics runs under the force held since the last call (zero-order hold), then takes the new one.
  const auto now = std::chrono::steady_clock::now();
  const double dt = fixed_step_s > 0.0 ? fixed_step_s
                    : d->stepped       ? std::min(0.01, std::chrono::duration<double>(now - d->last).count())
                                       : 0.0;
  d->last = now;
  d->stepped = true;
  step(*d, dt);
  const double norm = std::sqrt(fx * fx + fy * fy + fz * fz);
  const double scale = norm > d->max_force_n ? d->max_force_n / norm : 1.0;
  d->f = {fx * scale, fy * scale, fz * scale};
  d->t = {tx, ty, tz};
  d->gripper_force = fg;
  return scale < 1.0 ? kMotorSaturated : 0;
}
STANDIN_API int drdOpenID(char id) {
  std::lock_guard lock(mutex);
  return device(id) == nullptr ? -1 : id;
}
STANDIN_API bool drdIsInitialized(char id) {
  std::lock_guard lock(mutex);
  Device* d = device(id);
  log_call("drdIsInitialized", id);
  return d != nullptr && d->calibrated;
}
STANDIN_API int drdAutoInit(char id) {
  std::lock_guard lock(mutex);
  Device* d = device(id);
  if (d == nullptr) return -1;
  d->calibrated = true;
  d->p = {0, 0, 0};
  d->v = {0, 0, 0};
  log_call("drdAutoInit", id);
  return 0;
}
STANDIN_API int drdStop(bool /*keep_forces*/, char id) {
  std::lock_guard lock(mutex);
  return device(id) == nullptr ? -1 : 0;
}

// ---- the tests' controls ----

STANDIN_API void standin_dhd_setup(const char* spec) {
  std::lock_guard lock(mutex);
  fixed_step_s = 0.0;
  hang_call.store(kHangNone);
  released.store(false);
  setup_from(spec);
  call_log.clear();
  last_error = kNoError;
}
STANDIN_API void standin_dhd_set_step(double seconds) {
  std::lock_guard lock(mutex);
  fixed_step_s = seconds;
}
// kind: "unplug", "replug", "fail_next_force", "uncalibrated"; "hang_open" (any device), "hang_position",
// "hang_force" (this device's calls) and "release" (the hung call returns); false: no such device or kind.
STANDIN_API bool standin_dhd_fault(int index, const char* kind) {
  if (std::strncmp(kind, "hang_", 5) == 0 && hang_of(kind + 5) != kHangNone) {
    released.store(false);
    hang_device.store(std::strcmp(kind, "hang_open") == 0 ? -1 : index);
    hang_call.store(hang_of(kind + 5));
    return true;
  }
  if (std::strcmp(kind, "release") == 0) {
    released.store(true);
    hang_call.store(kHangNone);
    return true;
  }
  std::lock_guard lock(mutex);
  if (index < 0 || index >= static_cast<int>(devices.size())) return false;
  Device& d = devices[static_cast<std::size_t>(index)];
  if (std::strcmp(kind, "unplug") == 0)
    d.unplugged = true;
  else if (std::strcmp(kind, "replug") == 0)
    d.unplugged = false;
  else if (std::strcmp(kind, "fail_next_force") == 0)
    d.fail_next_force = true;
  else if (std::strcmp(kind, "uncalibrated") == 0)
    d.calibrated = false;
  else
    return false;
  return true;
}
STANDIN_API bool standin_dhd_hand(int index, double fx, double fy, double fz, unsigned buttons) {
  std::lock_guard lock(mutex);
  if (index < 0 || index >= static_cast<int>(devices.size())) return false;
  devices[static_cast<std::size_t>(index)].hand = {fx, fy, fz};
  devices[static_cast<std::size_t>(index)].buttons = buttons;
  return true;
}
// The force last written to the device (N), for the tests' checks.
STANDIN_API bool standin_dhd_force(int index, double* fx, double* fy, double* fz) {
  std::lock_guard lock(mutex);
  if (index < 0 || index >= static_cast<int>(devices.size())) return false;
  const Device& d = devices[static_cast<std::size_t>(index)];
  *fx = d.f[0];
  *fy = d.f[1];
  *fz = d.f[2];
  return true;
}
// The lifecycle calls so far, one per line ("dhdOpen(0)", "dhdEnableForce(on)(0)", ...).
// A copy taken under the lock (the SDK's thread may be logging): valid until the caller's thread asks again.
STANDIN_API const char* standin_dhd_call_log() {
  thread_local std::string copy;
  std::lock_guard lock(mutex);
  copy = call_log;
  return copy.c_str();
}
