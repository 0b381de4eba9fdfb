#include "bridge/dds_bridge.hpp"

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "bridge/cyclone_log.hpp"
#include "group/group_stage.hpp"
#include "session/device_session.hpp"

namespace hapticd::server {
namespace {

using Clock = std::chrono::steady_clock;

// Sets the calling thread's CPUs; returns the previous set (to restore), nullopt if none were given.
std::optional<cpu_set_t> set_cpus(const std::vector<int>& cpus) {
  if (cpus.empty()) return std::nullopt;
  cpu_set_t previous;
  if (pthread_getaffinity_np(pthread_self(), sizeof previous, &previous) != 0) return std::nullopt;
  cpu_set_t set;
  CPU_ZERO(&set);
  for (int c : cpus) CPU_SET(c, &set);
  if (pthread_setaffinity_np(pthread_self(), sizeof set, &set) != 0) return std::nullopt;
  return previous;
}

std::uint64_t snapshot_interval_of(const DdsSettings& settings, double rate_hz) {
  if (settings.state_rate_hz <= 0.0) return 1;
  return std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(rate_hz / settings.state_rate_hz)));
}

}  // namespace

void DdsBridge::pin_this_thread() const { (void)set_cpus(cpus_); }

DdsBridge::DdsBridge(const DdsSettings& settings, double rate_hz, std::vector<DeviceSession*> sessions,
                     std::vector<GroupStage*> stages, std::vector<int> dds_cpus, const EngineSocketSettings& socket,
                     const TeleoperationSettings& teleop)
    : settings_(settings), cpus_(std::move(dds_cpus)), links_(sessions, stages, settings) {
  const std::uint64_t interval = snapshot_interval_of(settings, rate_hz);
  double deadline = 1.0;
  for (DeviceSession* s : sessions) {
    deadline = std::min(deadline, s->chain().engine_deadline_s);
    s->set_snapshot_interval(interval);
  }
  for (GroupStage* g : stages) g->set_snapshot_interval(interval);
  cyclone_log::route_to_logger(settings.log_lines_per_s, 20.0);  // before Cyclone has anything to say
  // Cyclone's threads (receive, timed events, ...) start with the participant and inherit this thread's CPUs.
  const std::optional<cpu_set_t> previous = set_cpus(cpus_);
  std::vector<std::string> partitions = {"", dds::target_partition("*")};  // the default one, and every device's
  for (std::size_t i = 0; i < links_.size(); ++i) partitions.push_back(dds::target_partition(links_[i].device->name()));
  for (const GroupLink& g : links_.groups()) partitions.push_back(dds::target_partition(g.name));
  dds_ = std::make_unique<DdsEndpoints>(settings, dds::CommandTiming{deadline, 0.5}, links_.command_filter(),
                                        links_.request_filter(), links_.group_command_filter(), partitions);
  if (previous) (void)pthread_setaffinity_np(pthread_self(), sizeof *previous, &*previous);
  dds::check(dds_set_status_mask(dds_->request.get(), DDS_DATA_AVAILABLE_STATUS),
             "cannot set the request reader's status mask");
  dds::check(dds_waitset_attach(dds_->waitset.get(), dds_->request.get(), 1), "waitset");
  dds::check(dds_waitset_attach(dds_->waitset.get(), dds_->wake.get(), 2), "waitset");
  events_ = std::make_unique<EventSender>(dds_->event);
  publisher_ = std::make_unique<StatePublisher>(*dds_, links_, *events_, rate_hz, interval);
  intake_ = std::make_unique<CommandIntake>(*dds_, links_, *events_);
  dispatcher_ = std::make_unique<RequestDispatcher>(*dds_, links_, *events_, *publisher_, settings.claim_grace_s,
                                                    settings.claim_hold_s);
  lockstep_ = std::make_unique<LockstepSync>(
      settings_, links_, interval, [](void* self) { static_cast<DdsBridge*>(self)->wake_publisher(); }, this);
  if (socket.enabled) {
    socket_ = std::make_unique<EngineSocket>(
        socket, links_, dds_->peers, *intake_, [this] { (void)dds_set_guardcondition(dds_->wake.get(), true); }, cpus_);
    publisher_->set_engine_socket(socket_.get());
  }
  if (teleop.enabled) {
    DeviceLink* linked = links_.find(teleop.device);
    if (linked == nullptr) throw std::runtime_error("teleoperation: no device '" + teleop.device + "'");
    link_ = std::make_unique<TeleopLink>(teleop, *linked, dds_->participant, *events_);
    publisher_->set_teleop_link(link_.get());
  }
  for (std::size_t i = 0; i < links_.size(); ++i) publisher_->publish_description(i);
  for (const GroupLink& g : links_.groups()) publisher_->publish_group_description(g);
  intake_->listen();  // last: commands may arrive at once
}

DdsBridge::~DdsBridge() {
  stop();
  link_.reset();
  worlds_.reset();
  (void)dds_set_listener(dds_->command.get(), nullptr);  // no listener callback into the parts below
  (void)dds_set_listener(dds_->group_command.get(), nullptr);
}

void DdsBridge::relay_worlds(std::function<void(const hapticd_msg_World&)> sink) {
  worlds_ = std::make_unique<WorldRelay>(dds_->participant, std::move(sink));
}

void DdsBridge::start() {
  publisher_thread_ = std::thread([this] { publisher_thread(); });
  receiver_thread_ = std::thread([this] { receiver_thread(); });
  if (socket_) socket_->start();
}

void DdsBridge::stop() {
  if (!publisher_thread_.joinable() && !receiver_thread_.joinable()) return;
  if (socket_) socket_->stop();  // no more commands or requests from its clients
  stopping_.store(true);
  wake_publisher();
  ticket_.notify_all();
  (void)dds_set_guardcondition(dds_->wake.get(), true);
  if (publisher_thread_.joinable()) publisher_thread_.join();
  if (receiver_thread_.joinable()) receiver_thread_.join();
  publisher_->publish_states();  // the final state (mode off after the shutdown ramp)
  publisher_->publish_telemetry();
  cyclone_log::report_suppressed();
}

void DdsBridge::wake_publisher() noexcept {
  ticket_.fetch_add(1, std::memory_order_release);
  ticket_.notify_one();  // a futex wake when the publisher waits; no lock, no allocation
}

void DdsBridge::after_cycle(std::uint64_t index, bool lockstep) noexcept {
  wake_publisher();
  if (lockstep) lockstep_->after_cycle(index, stopping_);
}

void DdsBridge::publisher_thread() {
  pin_this_thread();
  std::uint32_t seen = ticket_.load(std::memory_order_acquire);
  while (!stopping_.load(std::memory_order_acquire)) {
    ticket_.wait(seen, std::memory_order_acquire);
    seen = ticket_.load(std::memory_order_acquire);
    publisher_->publish_states();
  }
}

void DdsBridge::receiver_thread() {
  pin_this_thread();
  const auto telemetry_period =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / settings_.telemetry_rate_hz));
  auto next_telemetry = Clock::now();
  auto next_log_report = Clock::now() + std::chrono::seconds(10);
  std::array<dds_attach_t, 4> triggered{};
  while (!stopping_.load(std::memory_order_acquire)) {
    const auto wait = std::clamp<std::int64_t>(
        std::chrono::duration_cast<std::chrono::nanoseconds>(next_telemetry - Clock::now()).count(), 0,
        kClaimCheckPeriodNs);
    (void)dds_waitset_wait(dds_->waitset.get(), triggered.data(), triggered.size(), wait);
    (void)dds_set_guardcondition(dds_->wake.get(), false);
    dispatcher_->handle_requests();
    if (socket_) socket_->answer_requests(*dispatcher_);
    dispatcher_->check_claims();
    dispatcher_->check_engine_deadlines();
    const auto now = Clock::now();
    if (now >= next_telemetry) {
      publisher_->publish_telemetry();
      next_telemetry = std::max(next_telemetry + telemetry_period, now);
    }
    if (now >= next_log_report) {
      cyclone_log::report_suppressed();
      next_log_report = now + std::chrono::seconds(10);
    }
  }
}

void DdsBridge::publish_fault_report(std::size_t device, const FaultReport& report) {
  publisher_->publish_fault_report(device, report);
}

void DdsBridge::announce(hapticd_msg_EventKind kind, std::string_view code, std::string_view message) {
  for (const auto& link : links_) events_->send(*link, kind, code, message);
}

std::uint64_t DdsBridge::commands_accepted(std::size_t device) const {
  std::lock_guard lock(links_[device].mutex);
  return links_[device].gate.accepted();
}
std::uint64_t DdsBridge::commands_rejected(std::size_t device) const {
  std::lock_guard lock(links_[device].mutex);
  return links_[device].gate.rejected_total();
}
std::array<std::uint64_t, dds::kRejectReasons> DdsBridge::rejected_by_reason(std::size_t device) const {
  std::lock_guard lock(links_[device].mutex);
  return links_[device].gate.rejected();
}
std::string DdsBridge::owner(std::size_t device) const {
  std::lock_guard lock(links_[device].mutex);
  return links_[device].gate.owner();
}
std::uint64_t DdsBridge::deadline_misses(std::size_t device) const { return links_[device].deadline_misses.load(); }

RoundTripStatistics DdsBridge::round_trip() const {
  LatencyHistogram round_trips;
  RoundTripStatistics counts;
  for (const auto& d : links_) d->round_trip.merge_into(round_trips, counts);
  return summarise_round_trips(round_trips, counts);
}

}  // namespace hapticd::server
