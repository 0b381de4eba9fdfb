#include "gate/gate.hpp"

#include <pthread.h>
#include <sched.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "executor/loop_clock.hpp"
#include "group/group_stage.hpp"
#include "hapticd/dds/conversion.hpp"
#include "session/device_session.hpp"

namespace hapticd::server {
namespace {

using Clock = std::chrono::steady_clock;

std::uint64_t snapshot_interval_of(const GateSettings& settings, double rate_hz) {
  if (settings.state_rate_hz <= 0.0) return 1;
  return std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(rate_hz / settings.state_rate_hz)));
}

}  // namespace

Gate::Gate(const GateSettings& settings, double rate_hz, std::vector<DeviceSession*> sessions,
           std::vector<GroupStage*> stages, std::vector<int> cpus)
    : settings_(settings),
      cpus_(std::move(cpus)),
      interval_(snapshot_interval_of(settings, rate_hz)),
      devices_(sessions, stages, settings),
      states_(devices_, events_, rate_hz, interval_),
      dispatcher_(std::make_unique<RequestDispatcher>(devices_, events_, states_, settings.claim_grace_s,
                                                      settings.claim_hold_s, settings.tuning_by_anyone)),
      lockstep_(
          settings_, devices_, interval_, [](void* self) { static_cast<Gate*>(self)->wake_publisher(); }, this) {
  for (DeviceSession* s : sessions) s->set_snapshot_interval(interval_);
  for (GroupStage* g : stages) g->set_snapshot_interval(interval_);
  // The session's scene, which every device's chain holds (the same one): the doors edit it through here.
  for (DeviceSession* s : sessions)
    if (s->chain().scene && !scene_) scene_ = std::make_unique<SceneGate>(*s->chain().scene->object);
}

Gate::~Gate() { stop(); }

void Gate::add_door(Door& door) {
  doors_.push_back(&door);
  events_.set_doors(doors_);
  states_.set_doors(doors_);
  dispatcher_->set_doors(doors_);
}

void Gate::pin_this_thread() const {
  if (cpus_.empty()) return;
  cpu_set_t set;
  CPU_ZERO(&set);
  for (int c : cpus_) CPU_SET(c, &set);
  (void)pthread_setaffinity_np(pthread_self(), sizeof set, &set);
}

void Gate::start() {
  for (std::size_t i = 0; i < devices_.size(); ++i) states_.publish_description(i);
  for (const GroupGate& g : devices_.groups()) states_.publish_group_description(g);
  publisher_thread_ = std::thread([this] { publisher_thread(); });
  service_thread_ = std::thread([this] { service_thread(); });
  started_ = true;
  for (Door* door : doors_) door->start();
}

void Gate::stop() {
  if (!started_) return;
  started_ = false;
  for (Door* door : doors_) door->stop();  // no more commands or requests
  stopping_.store(true);
  wake_publisher();
  wake();
  if (publisher_thread_.joinable()) publisher_thread_.join();
  if (service_thread_.joinable()) service_thread_.join();
  states_.publish_states();  // the final state (mode off after the shutdown ramp)
  states_.publish_telemetry();
}

void Gate::wake_publisher() noexcept {
  ticket_.fetch_add(1, std::memory_order_release);
  ticket_.notify_one();  // a futex wake when the publisher waits; no lock, no allocation
}

void Gate::wake() noexcept {
  {
    std::lock_guard lock(wake_mutex_);
    woken_ = true;
  }
  wake_cv_.notify_one();
}

void Gate::after_cycle(std::uint64_t index, bool lockstep) noexcept {
  wake_publisher();
  if (lockstep) lockstep_.after_cycle(index, stopping_);
}

void Gate::publisher_thread() {
  pin_this_thread();
  std::uint32_t seen = ticket_.load(std::memory_order_acquire);
  while (!stopping_.load(std::memory_order_acquire)) {
    ticket_.wait(seen, std::memory_order_acquire);
    seen = ticket_.load(std::memory_order_acquire);
    states_.publish_states();
  }
}

void Gate::service_thread() {
  pin_this_thread();
  const auto telemetry_period =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / settings_.telemetry_rate_hz));
  auto next_telemetry = Clock::now();
  while (!stopping_.load(std::memory_order_acquire)) {
    {
      std::unique_lock lock(wake_mutex_);
      const auto until = std::min(next_telemetry, Clock::now() + std::chrono::nanoseconds(kServicePeriodNs));
      wake_cv_.wait_until(lock, until, [this] { return woken_; });
      woken_ = false;
    }
    if (stopping_.load(std::memory_order_acquire)) break;
    for (Door* door : doors_) door->answer_requests(*dispatcher_);
    dispatcher_->check_claims();
    if (scene_ && scene_->check_claim([this](const Sender& s) { return dispatcher_->gone(s); }))
      spdlog::info("the scene's claim ended: its owner's channel is gone");
    for (Door* door : doors_) door->service();
    const auto now = Clock::now();
    if (now >= next_telemetry) {
      states_.publish_telemetry();
      next_telemetry = std::max(next_telemetry + telemetry_period, now);
    }
  }
}

CommandGate::Verdict Gate::admit(const hapticd_msg_EngineCommand& c, const Sender& sender, std::int64_t source_ns) {
  DeviceGate* d = devices_.find(dds::text_of(c.device));
  if (d == nullptr) {
    devices_.count_unknown_command();
    return {false, dds::RejectReason::malformed};
  }
  return admit(*d, c, sender, source_ns);
}

CommandGate::Verdict Gate::admit(DeviceGate& d, const hapticd_msg_EngineCommand& c, const Sender& sender,
                                 std::int64_t source_ns) {
  const std::lock_guard one_at_a_time(admit_mutex_);
  CommandGate::Verdict v;
  {
    std::lock_guard lock(d.mutex);
    v = d.gate.admit(c, sender, source_ns, dds::wall_clock_ns());
  }
  if (!v.accepted) {
    if (d.reject_events[static_cast<std::size_t>(v.reason)]++ % 100 == 0)  // the first, then every 100th per reason
      events_.send(d, hapticd_msg_EVENT_ENGINE_REJECTED, dds::to_string(v.reason),
                   "engine command rejected from '" + std::string(dds::text_of(c.engine)) +
                       "': " + std::string(dds::to_string(v.reason)));
    return v;
  }
  const std::int64_t state_written_ns = d.round_trip.command_accepted(c.serial, c.state_serial);
  d.device->engine_input(dds::to_engine_input(c));
  d.round_trip.command_handed_over(state_written_ns, monotonic_now_ns());
  if (c.state_serial > 0) {
    if (c.state_serial > d.answered.load(std::memory_order_relaxed))
      d.answered.store(c.state_serial, std::memory_order_release);
    d.synced.store(true, std::memory_order_release);
  }
  return v;
}

void Gate::publish_fault_report(std::size_t device, const FaultReport& report) {
  states_.publish_fault_report(device, report);
}

void Gate::announce(hapticd_msg_EventKind kind, std::string_view code, std::string_view message) {
  for (const auto& d : devices_) events_.send(*d, kind, code, message);
}

std::uint64_t Gate::commands_accepted(std::size_t device) const {
  std::lock_guard lock(devices_[device].mutex);
  return devices_[device].gate.accepted();
}
std::uint64_t Gate::commands_rejected(std::size_t device) const {
  std::lock_guard lock(devices_[device].mutex);
  return devices_[device].gate.rejected_total();
}
std::array<std::uint64_t, dds::kRejectReasons> Gate::rejected_by_reason(std::size_t device) const {
  std::lock_guard lock(devices_[device].mutex);
  return devices_[device].gate.rejected();
}
std::string Gate::owner(std::size_t device) const {
  std::lock_guard lock(devices_[device].mutex);
  return devices_[device].gate.owner();
}

RoundTripStatistics Gate::round_trip() const {
  LatencyHistogram round_trips;
  RoundTripStatistics counts;
  for (const auto& d : devices_) d->round_trip.merge_into(round_trips, counts);
  return summarise_round_trips(round_trips, counts);
}

}  // namespace hapticd::server
