#include "hd_link.hpp"

#include <chrono>
#include <mutex>
#include <thread>

#include "hapticd/realtime/tick_signal.hpp"

namespace hapticd::plugins::openhaptics {
namespace {

// The HD scheduler is one per process, shared by every device: started by the first enable(), stopped by the
// last disable().
std::mutex scheduler_mutex;
int scheduler_users = 0;

HDCallbackCode servo_callback(void* link) { return static_cast<HdLink*>(link)->servo(); }

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

HdLink::HdLink(std::unique_ptr<VendorLibrary> loaded)
    : library(std::move(loaded)), hd(std::make_unique<HdApi>(*library)) {}

HdLink::~HdLink() { close(); }

HDCallbackCode HdLink::servo() noexcept {
  if (!running.load(std::memory_order_acquire)) {  // the end: one frame with no force, then done
    const double zero[3] = {0, 0, 0};
    hd->begin_frame(handle);
    hd->set_doublev(kCurrentForce, zero);
    if (actuated_torque) hd->set_doublev(kCurrentTorque, zero);
    hd->end_frame(handle);
    ended.store(true, std::memory_order_release);
    return kCallbackDone;
  }
  HdSample s;
  hd->begin_frame(handle);
  hd->get_doublev(kCurrentPosition, s.position_mm.data());
  hd->get_doublev(kCurrentVelocity, s.velocity_mm_s.data());
  hd->get_doublev(kCurrentTransform, s.transform.data());
  hd->get_doublev(kCurrentAngularVelocity, s.angular_velocity.data());
  hd->get_doublev(kCurrentJointAngles, s.joint_angles.data());
  hd->get_doublev(kCurrentGimbalAngles, s.gimbal_angles.data());
  hd->get_integerv(kCurrentButtons, &s.buttons);
  s.errors = end_errors_;  // the previous frame's end first
  s.errors.drain(*hd);
  s.time_ns = realtime::TickSignal::now_ns();
  handoff.publish(s, s.time_ns);
  handoff.next_command(applied_);  // on the device's clock: the loop's answer to this tick
  hd->set_doublev(kCurrentForce, applied_.force_n.data());
  if (actuated_torque) hd->set_doublev(kCurrentTorque, applied_.torque_mnm.data());
  hd->end_frame(handle);
  end_errors_ = HdErrors{};  // told with the next sample
  end_errors_.drain(*hd);
  return kCallbackContinue;
}

void HdLink::start() noexcept {
  failed = "";
  applied_ = HdCommand{};
  end_errors_ = HdErrors{};
  sdk.calling("hdMakeCurrentDevice");
  hd->make_current_device(handle);
  (void)HdErrors::of(*hd);  // nothing of configure's queries may be told as this start's, or a frame's, error
  sdk.calling("hdEnable");
  hd->enable(kForceOutput);
  if (errors = HdErrors::of(*hd); errors.count > 0) {
    failed = "enabling forces";
    return;
  }
  ended.store(false);
  running.store(true);
  sdk.calling("hdScheduleAsynchronous");
  callback = hd->schedule_asynchronous(&servo_callback, this, kMaxSchedulerPriority);
  if (errors = HdErrors::of(*hd); errors.count > 0) {
    running.store(false);
    failed = "scheduling the servo callback";
    return;
  }
  scheduled = true;
  {
    std::lock_guard lock(scheduler_mutex);
    sdk.calling("hdStartScheduler");
    if (scheduler_users++ == 0) hd->start_scheduler();
  }
  if (errors = HdErrors::of(*hd); errors.count > 0) failed = "starting the HD scheduler";
}

void HdLink::close() noexcept {
  if (handle == kInvalidHandle) return;
  running.store(false, std::memory_order_release);
  if (scheduled) {
    // The callback's last frame writes no force (on the scheduler's thread, where frames belong); 0.1 s at most.
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(100);
    while (!ended.load(std::memory_order_acquire) && std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    sdk.calling("hdUnschedule");
    hd->unschedule(callback);
    scheduled = false;
    std::lock_guard lock(scheduler_mutex);
    sdk.calling("hdStopScheduler");
    if (--scheduler_users == 0) hd->stop_scheduler();
  }
  sdk.calling("hdMakeCurrentDevice");
  hd->make_current_device(handle);
  sdk.calling("hdDisable");
  hd->disable(kForceOutput);
  sdk.calling("hdDisableDevice");
  hd->disable_device(handle);
  (void)HdErrors::of(*hd);
  handle = kInvalidHandle;
}

}  // namespace hapticd::plugins::openhaptics
