#include "dds/dds_bridge.hpp"

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "dds/cyclone_log.hpp"
#include "hapticd/dds/conversion.hpp"
#include "hapticd/dds/endpoints.hpp"
#include "session/device_session.hpp"

namespace hapticd::server {
namespace {

using Clock = std::chrono::steady_clock;

std::int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
}

hapticd_msg_DeviceMode mode_of(const DeviceSnapshot& s) {
  if (s.fault != DeviceFault::none) return hapticd_msg_MODE_SAFE;
  if (s.stopping) return hapticd_msg_MODE_STOPPING;
  return hapticd_msg_MODE_RUNNING;
}

}  // namespace

struct DdsBridge::Device {
  Device(DeviceSession* s, const DdsSettings& settings)
      : session(s),
        gate(dds::CommandBounds{settings.max_force_n, settings.max_torque_nm, settings.max_stiffness_n_per_m,
                                settings.max_rotational_stiffness_n_m_per_rad, settings.max_damping_n_s_per_m,
                                settings.max_rotational_damping_n_m_s, settings.max_distance_m, settings.max_speed_m_s,
                                settings.max_angular_speed_rad_s},
             settings.max_sample_age_s) {}
  DeviceSession* session;
  mutable std::mutex mutex;  // the gate (the receiver changes it; the others read owner and counters)
  CommandGate gate;
  // The claim: the request writer that made it (the claimant's participant is gone once it is unmatched) and
  // when (steady clock; a claimant without a live command writer is given claim_grace_s).
  dds_instance_handle_t claim_writer = 0;
  std::int64_t claimed_ns = 0;
  std::atomic<dds_instance_handle_t> instance{0};  // its instance on the command reader (listener -> receiver)
  std::atomic<std::uint64_t> answered{0};  // newest state serial an accepted command answered
  std::atomic<bool> synced{false};         // the owner answers every state (lockstep sync waits for it)
  std::atomic<std::uint64_t> deadline_misses{0};
  std::uint64_t requests = 0;
  std::array<std::uint64_t, dds::kRejectReasons> reject_events{};
  // Publisher thread.
  DeviceSnapshot snapshot;
  bool have_snapshot = false;
  DeviceFault last_fault = DeviceFault::none;
  std::uint64_t last_faults = 0;
  hapticd_msg_DeviceMode last_mode = hapticd_msg_MODE_STARTING;
  int last_scheme = 0;
  bool last_stale = false;
  std::atomic<std::uint64_t> states{0};     // read by telemetry
  std::atomic<std::int64_t> loop_time_ns{0}; // of the newest snapshot, for events from any thread
  RoundTripProbe round_trip;
  hapticd_msg_DeviceState last_state{};
  std::int64_t last_write_ns = 0;
  Pose start_pose;
};

struct DdsBridge::Dds {
  Dds(const DdsSettings& s, const dds::CommandTiming& timing, const dds_topic_filter& command_filter,
      const dds_topic_filter& request_filter)
      : participant(dds::ParticipantOptions{s.domain_id, s.cyclone_config}),
        description(participant),
        state(participant),
        event(participant),
        telemetry(participant),
        fault_report(participant),
        reply(participant),
        command(participant, timing, &command_filter),
        request(participant, {}, &request_filter),
        waitset(dds::check(dds_create_waitset(participant.get()), "cannot create a DDS waitset")),
        wake(dds::check(dds_create_guardcondition(participant.get()), "cannot create a DDS guard condition")),
        peers(static_cast<std::size_t>(s.max_peers)) {}
  dds::Participant participant;
  dds::Writer<hapticd_msg_DeviceDescription> description;
  dds::Writer<hapticd_msg_DeviceState> state;
  dds::Writer<hapticd_msg_Event> event;
  dds::Writer<hapticd_msg_Telemetry> telemetry;
  dds::Writer<hapticd_msg_FaultReport> fault_report;
  dds::Writer<hapticd_msg_ControlReply> reply;
  dds::Reader<hapticd_msg_EngineCommand> command;
  dds::Reader<hapticd_msg_ControlRequest> request;
  dds::Entity waitset;
  dds::Entity wake;
  PeerDirectory peers;  // who wrote a command or request: the writer's participant
};

namespace {
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
}  // namespace

void DdsBridge::pin_this_thread() const { (void)set_cpus(cpus_); }

DdsBridge::DdsBridge(const DdsSettings& settings, double rate_hz, std::vector<DeviceSession*> sessions,
                     std::vector<int> dds_cpus)
    : settings_(settings), rate_hz_(rate_hz), cpus_(std::move(dds_cpus)) {
  snapshot_interval_ = settings.state_rate_hz > 0.0
                           ? std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(rate_hz / settings.state_rate_hz)))
                           : 1;
  double deadline = 1.0;
  for (DeviceSession* s : sessions) deadline = std::min(deadline, s->chain().engine_deadline_s);
  for (DeviceSession* s : sessions) {
    s->set_snapshot_interval(snapshot_interval_);
    devices_.push_back(std::make_unique<Device>(s, settings));
  }
  cyclone_log::route_to_logger(settings.log_lines_per_s, 20.0);  // before Cyclone has anything to say
  // Engine commands are taken on Cyclone's receive thread (a listener): no thread wake-up between a command's
  // arrival and its hand-over to the loop. Requests, engine health and telemetry are the receiver thread's.
  // Cyclone's threads (receive, timed events, ...) start with the participant and inherit this thread's CPUs.
  const std::optional<cpu_set_t> previous = set_cpus(cpus_);
  // Samples for a device this server does not drive are dropped before Cyclone stores them (and counted): an
  // attacker inventing device names creates no state here.
  const dds_topic_filter command_filter{DDS_TOPIC_FILTER_SAMPLE_ARG, {.sample_arg = &DdsBridge::command_for_us}, this};
  const dds_topic_filter request_filter{DDS_TOPIC_FILTER_SAMPLE_ARG, {.sample_arg = &DdsBridge::request_for_us}, this};
  dds_ = std::make_unique<Dds>(settings, dds::CommandTiming{deadline, 0.5}, command_filter, request_filter);
  if (previous) (void)pthread_setaffinity_np(pthread_self(), sizeof *previous, &*previous);
  dds::check(dds_set_status_mask(dds_->request.get(), DDS_DATA_AVAILABLE_STATUS), "cannot set the request reader's status mask");
  dds::check(dds_waitset_attach(dds_->waitset.get(), dds_->request.get(), 1), "waitset");
  dds::check(dds_waitset_attach(dds_->waitset.get(), dds_->wake.get(), 2), "waitset");
  for (auto& d : devices_) publish_description(*d);
  // Last: the listener may run at once, and needs everything above.
  const dds::Listener listener(dds_create_listener(this));
  dds_lset_data_available(listener.get(), [](dds_entity_t, void* self) { static_cast<DdsBridge*>(self)->handle_commands(); });
  // A command writer that loses its liveliness (its process died or froze): the receiver checks the claims.
  dds_lset_liveliness_changed(listener.get(), [](dds_entity_t, const dds_liveliness_changed_status_t status, void* self) {
    auto* bridge = static_cast<DdsBridge*>(self);
    bridge->dds_->peers.liveliness_changed(status);
    (void)dds_set_guardcondition(bridge->dds_->wake.get(), true);
  });
  dds_->command.set_listener(listener.get());
}

DdsBridge::~DdsBridge() { stop(); }

void DdsBridge::start() {
  publisher_ = std::thread([this] { publisher_thread(); });
  receiver_ = std::thread([this] { receiver_thread(); });
}

void DdsBridge::stop() {
  if (!publisher_.joinable() && !receiver_.joinable()) return;
  stopping_.store(true);
  ticket_.fetch_add(1);
  ticket_.notify_all();
  (void)dds_set_guardcondition(dds_->wake.get(), true);
  if (publisher_.joinable()) publisher_.join();
  if (receiver_.joinable()) receiver_.join();
  publish_states();  // the final state (mode off after the shutdown ramp)
  publish_telemetry();
  cyclone_log::report_suppressed();
}

void DdsBridge::after_cycle(std::uint64_t index, bool lockstep) noexcept {
  ticket_.fetch_add(1, std::memory_order_release);
  ticket_.notify_one();  // a futex wake when the publisher waits; no lock, no allocation
  if (!lockstep || !settings_.lockstep_sync || index % snapshot_interval_ != 0) return;
  if (index == 0 && settings_.lockstep_start_wait_s > 0.0) {
    // Before the virtual clock runs away: wait for an engine to claim a device and answer its first state
    // (the publisher repeats the state meanwhile, for a reader that matches late).
    const auto give_up = Clock::now() + std::chrono::duration<double>(settings_.lockstep_start_wait_s);
    const auto any_synced = [&] {
      return std::any_of(devices_.begin(), devices_.end(), [](const auto& d) { return d->synced.load(std::memory_order_acquire); });
    };
    while (!any_synced() && Clock::now() < give_up && !stopping_.load(std::memory_order_acquire)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      ticket_.fetch_add(1, std::memory_order_release);
      ticket_.notify_one();
    }
  }
  // Lockstep: wait until each engine that answers every state has answered this one (bounded in wall time).
  const std::uint64_t serial = index / snapshot_interval_ + 1;
  for (auto& d : devices_) {
    if (!d->synced.load(std::memory_order_acquire)) continue;
    const auto give_up = Clock::now() + std::chrono::duration<double>(settings_.lockstep_wait_s);
    int spins = 0;
    while (d->answered.load(std::memory_order_acquire) < serial && d->synced.load(std::memory_order_acquire)) {
      if (++spins < 200) {
        std::this_thread::yield();
        continue;
      }
      if (Clock::now() > give_up) {
        d->synced.store(false, std::memory_order_release);  // stop waiting for it until it answers again
        lockstep_timeouts_.fetch_add(1, std::memory_order_relaxed);
        break;
      }
      std::this_thread::sleep_for(std::chrono::microseconds(20));
    }
  }
}

// ---- publisher ----

void DdsBridge::publisher_thread() {
  pin_this_thread();
  std::uint32_t seen = ticket_.load(std::memory_order_acquire);
  while (!stopping_.load(std::memory_order_acquire)) {
    ticket_.wait(seen, std::memory_order_acquire);
    seen = ticket_.load(std::memory_order_acquire);
    publish_states();
  }
}

void DdsBridge::publish_states() {
  for (auto& dp : devices_) {
    Device& d = *dp;
    if (!d.session->take_snapshot(d.snapshot)) {
      // Nothing new (the loop waits, e.g. for the first engine in lockstep): repeat the last state now and
      // then, for readers that matched after it was written.
      if (d.states.load(std::memory_order_relaxed) > 0 && steady_ns() - d.last_write_ns > 10'000'000) {
        (void)dds_->state.write(d.last_state);
        d.last_write_ns = steady_ns();
      }
      continue;
    }
    const DeviceSnapshot& s = d.snapshot;
    if (!d.have_snapshot) {
      d.have_snapshot = true;
      d.start_pose = s.handle_pose;
      publish_description(d);  // now with the start pose
    }
    hapticd_msg_DeviceState m{};
    dds::set_text(m.device, d.session->name());
    m.serial = s.cycle / snapshot_interval_ + 1;
    m.cycle = s.cycle;
    m.loop_time_ns = s.time_ns;
    dds::to_msg(s.handle_pose, m.pose);
    dds::to_msg(s.handle_twist, m.twist);
    dds::to_msg(s.operator_wrench, m.operator_wrench);
    dds::to_msg(s.environment_wrench, m.environment_wrench);
    dds::to_msg(s.target_pose, m.target_pose);
    m.dof = static_cast<std::int32_t>(s.position.size());
    for (Eigen::Index i = 0; i < s.position.size() && i < hapticd_msg_MAX_JOINTS; ++i) {
      m.position[i] = s.position[i];
      m.velocity[i] = i < s.velocity.size() ? s.velocity[i] : 0.0;
      m.torque[i] = i < s.torque.size() ? s.torque[i] : 0.0;
    }
    m.mode = mode_of(s);
    m.flags = (s.saturated ? hapticd_msg_FLAG_TORQUE_SATURATED : 0u) |
              (s.engine_weight > 0.0 && !s.engine_stale ? hapticd_msg_FLAG_ENGINE_ACTIVE : 0u) |
              (s.engine_stale ? hapticd_msg_FLAG_ENGINE_STALE : 0u) |
              (s.estop ? hapticd_msg_FLAG_ESTOP : 0u) | (s.fault != DeviceFault::none ? hapticd_msg_FLAG_FAULT : 0u) |
              (s.switching ? hapticd_msg_FLAG_SWITCHING : 0u) | (s.safe_damping ? hapticd_msg_FLAG_SAFE_DAMPING : 0u) |
              (s.limit_engaged ? hapticd_msg_FLAG_LIMIT_ENGAGED : 0u) |
              (s.render_limited ? hapticd_msg_FLAG_RENDER_LIMITED : 0u) |
              (s.thermal_derating ? hapticd_msg_FLAG_THERMAL_DERATING : 0u) |
              (s.passivity_control ? hapticd_msg_FLAG_PASSIVITY_CONTROL : 0u);
    dds::set_text(m.fault, s.fault == DeviceFault::none ? std::string_view() : fault_code(s.fault));
    dds::set_text(m.scheme, d.session->active_scheme());
    {
      std::lock_guard lock(d.mutex);
      dds::set_text(m.owner, d.gate.owner());
    }
    m.engine_serial = s.engine_sequence;
    fill_loop_summary(m.loop);
    d.round_trip.command_applied(s.engine_sequence, s.cycle);
    d.round_trip.state_written(m.serial, s.cycle, steady_ns());
    (void)dds_->state.write(m);
    d.states.fetch_add(1, std::memory_order_relaxed);
    d.loop_time_ns.store(s.time_ns, std::memory_order_relaxed);
    d.last_state = m;
    d.last_write_ns = steady_ns();

    // Events the snapshots reveal.
    if (m.mode != d.last_mode) {
      static constexpr const char* kModes[] = {"starting", "running", "stopping", "safe", "off"};
      const auto mode = static_cast<std::size_t>(m.mode);
      send_event(d, hapticd_msg_EVENT_MODE, mode < 5 ? kModes[mode] : "?", std::string("mode: ") + (mode < 5 ? kModes[mode] : "?"));
      d.last_mode = m.mode;
    }
    if (s.fault != d.last_fault || s.faults != d.last_faults) {
      if (s.fault == DeviceFault::none) {
        send_event(d, hapticd_msg_EVENT_RECOVERED, fault_code(d.last_fault), "the device left its safe mode on request");
      } else {
        send_event(d, s.fault == DeviceFault::emergency_stop ? hapticd_msg_EVENT_ESTOP : hapticd_msg_EVENT_FAULT,
                   fault_code(s.fault),
                   std::string(to_string(s.fault)) + ": the device is in its safe mode (damping, then zero torque); "
                                                     "its history is on the fault report topic");
      }
      d.last_fault = s.fault;
      d.last_faults = s.faults;
    }
    if (s.scheme != d.last_scheme && !d.session->chain().schemes.empty()) {
      d.last_scheme = s.scheme;
      const std::string& name = d.session->chain().schemes[static_cast<std::size_t>(s.scheme)].name;
      send_event(d, hapticd_msg_EVENT_SCHEME, name, "switched to scheme " + name);
    }
    const bool stale = s.engine_stale;
    if (stale && !d.last_stale)
      send_event(d, hapticd_msg_EVENT_ENGINE_STALE, "deadline", "engine input missed its deadline: forces fade out");
    d.last_stale = stale;
  }
}

void DdsBridge::fill_loop_summary(hapticd_msg_LoopSummary& loop) const {
  loop.rate_hz = rate_hz_;
  if (live_ == nullptr) return;
  loop.cycles = live_->cycles.load(std::memory_order_relaxed);
  loop.overruns = live_->overruns.load(std::memory_order_relaxed);
  loop.latency_max_us = static_cast<double>(live_->window_latency_max_ns.load(std::memory_order_relaxed)) * 1e-3;
  loop.compute_max_us = static_cast<double>(live_->window_compute_max_ns.load(std::memory_order_relaxed)) * 1e-3;
}

void DdsBridge::publish_description(Device& d) {
  const DeviceSession& s = *d.session;
  const DeviceDescription& desc = s.description();
  hapticd_msg_DeviceDescription m{};
  dds::set_text(m.device, s.name());
  m.version = hapticd_msg_VERSION;
  dds::set_text(m.device_plugin, s.chain().device.descriptor->name);
  m.simulated = std::string_view(s.chain().device.descriptor->name).substr(0, 3) == "sim";
  m.rate_hz = rate_hz_;
  m.dof = desc.dof();
  for (int i = 0; i < desc.dof() && i < hapticd_msg_MAX_JOINTS; ++i) {
    const JointDescription& j = desc.joints[static_cast<std::size_t>(i)];
    dds::set_text(m.joint_names[i], j.name);
    m.position_min[i] = j.position_min;
    m.position_max[i] = j.position_max;
    m.velocity_max[i] = j.velocity_max;
    m.torque_peak[i] = j.torque_peak_nm;
    m.torque_continuous[i] = j.torque_continuous_nm;
  }
  dds::set_text(m.base_frame, "world");
  dds::set_text(m.handle_frame, desc.handle_frame);
  if (d.have_snapshot) dds::to_msg(d.start_pose, m.start_pose);  // else all zeros: not known yet
  const auto& schemes = s.chain().schemes;
  m.scheme_count = static_cast<std::int32_t>(std::min<std::size_t>(schemes.size(), hapticd_msg_MAX_SCHEMES));
  for (std::int32_t k = 0; k < m.scheme_count; ++k) {
    const SchemeChain& sc = schemes[static_cast<std::size_t>(k)];
    dds::set_text(m.schemes[k], sc.name);
    dds::set_text(m.scheme_virtual_model[k], sc.virtual_model ? std::string_view(sc.virtual_model->descriptor->name) : "");
  }
  m.command_deadline_s = s.chain().engine_deadline_s;
  m.command_fade_s = s.chain().engine_fade_s;
  (void)dds_->description.write(m);
}

void DdsBridge::publish_fault_report(std::size_t device, const FaultReport& report) {
  Device& d = *devices_.at(device);
  auto m = std::make_unique<hapticd_msg_FaultReport>();  // 100 kB: not on the stack
  *m = hapticd_msg_FaultReport{};
  dds::set_text(m->device, d.session->name());
  m->serial = report.serial;
  dds::set_text(m->fault, fault_code(report.fault));
  dds::set_text(m->message, to_string(report.fault));
  m->cycle = report.cycle;
  m->loop_time_ns = report.time_ns;
  m->dof = d.session->description().dof();
  m->record_count = static_cast<std::int32_t>(std::min<std::uint32_t>(report.count, hapticd_msg_MAX_HISTORY));
  for (std::int32_t k = 0; k < m->record_count; ++k) {
    const HistoryRecord& r = report.records[static_cast<std::size_t>(k)];
    hapticd_msg_CycleRecord& o = m->records[k];
    o.cycle = r.cycle;
    o.loop_time_ns = r.time_ns;
    for (Eigen::Index i = 0; i < r.position.size() && i < hapticd_msg_MAX_JOINTS; ++i) {
      o.position[i] = r.position[i];
      o.velocity[i] = i < r.velocity.size() ? r.velocity[i] : 0.0;
      o.torque[i] = i < r.torque.size() ? r.torque[i] : 0.0;
    }
    for (int i = 0; i < 3; ++i) {
      o.handle_position[i] = r.handle_position[i];
      o.handle_velocity[i] = r.handle_velocity[i];
      o.operator_force[i] = r.operator_force[i];
      o.environment_force[i] = r.environment_force[i];
    }
    o.flags = r.flags;
  }
  (void)dds_->fault_report.write(*m);
}

void DdsBridge::announce(int kind, std::string_view code, std::string_view message) {
  for (auto& d : devices_) send_event(*d, kind, code, message);
}

void DdsBridge::send_event(Device& d, int kind, std::string_view code, std::string_view message) {
  hapticd_msg_Event e{};
  dds::set_text(e.device, d.session->name());
  e.serial = event_serial_.fetch_add(1) + 1;
  e.loop_time_ns = d.loop_time_ns.load(std::memory_order_relaxed);
  e.kind = static_cast<hapticd_msg_EventKind>(kind);
  dds::set_text(e.code, code);
  dds::set_text(e.message, message);
  (void)dds_->event.write(e);
}

// ---- receiver ----

void DdsBridge::receiver_thread() {
  pin_this_thread();
  const auto telemetry_period = std::chrono::duration<double>(1.0 / settings_.telemetry_rate_hz);
  auto next_telemetry = Clock::now();
  auto next_log_report = Clock::now() + std::chrono::seconds(10);
  std::array<dds_attach_t, 4> triggered{};
  while (!stopping_.load(std::memory_order_acquire)) {
    const auto now = Clock::now();
    const auto wait = std::clamp<std::int64_t>(
        std::chrono::duration_cast<std::chrono::nanoseconds>(next_telemetry - now).count(), 0, kClaimCheckPeriodNs);
    (void)dds_waitset_wait(dds_->waitset.get(), triggered.data(), triggered.size(), wait);
    (void)dds_set_guardcondition(dds_->wake.get(), false);
    handle_requests();
    check_claims();
    check_engine_deadlines();
    if (Clock::now() >= next_log_report) {
      cyclone_log::report_suppressed();
      next_log_report = Clock::now() + std::chrono::seconds(10);
    }
    if (Clock::now() >= next_telemetry) {
      publish_telemetry();
      next_telemetry += std::chrono::duration_cast<Clock::duration>(telemetry_period);
      if (next_telemetry < Clock::now()) next_telemetry = Clock::now() + std::chrono::duration_cast<Clock::duration>(telemetry_period);
    }
  }
}

void DdsBridge::handle_commands() {
  // One at a time: Cyclone may call the listener from more than one thread (local writers deliver on their
  // own thread), and the reader's sample buffers are shared.
  const std::lock_guard one_at_a_time(command_take_mutex_);
  dds_->command.take([&](const hapticd_msg_EngineCommand& c, const dds_sample_info_t& info) {
    const std::int64_t now_wall = dds::wall_clock_ns();
    const std::string_view device = dds::text_of(c.device);
    // Who wrote it (a writer no longer matched has no participant: it is nobody's command).
    const Sender sender{dds_->peers.participant_of(dds_->command.get(), info.publication_handle).value_or(PeerId{}),
                        info.publication_handle};
    for (auto& dp : devices_) {
      Device& d = *dp;
      if (device != d.session->name()) continue;
      d.instance.store(info.instance_handle, std::memory_order_relaxed);
      CommandGate::Verdict v;
      {
        std::lock_guard lock(d.mutex);
        v = d.gate.admit(c, sender, info.source_timestamp, now_wall);
      }
      if (!v.accepted) {
        const auto r = static_cast<std::size_t>(v.reason);
        if (d.reject_events[r]++ % 100 == 0)  // the first, then every 100th per reason
          send_event(d, hapticd_msg_EVENT_ENGINE_REJECTED, dds::to_string(v.reason),
                     "engine command rejected from '" + std::string(dds::text_of(c.engine)) + "': " +
                         std::string(dds::to_string(v.reason)));
        return;
      }
      const std::int64_t state_written_ns = d.round_trip.command_accepted(c.serial, c.state_serial);
      d.session->publish_engine_input(dds::to_engine_input(c));
      d.round_trip.command_handed_over(state_written_ns, steady_ns());
      if (c.state_serial > 0) {
        if (c.state_serial > d.answered.load(std::memory_order_relaxed)) d.answered.store(c.state_serial, std::memory_order_release);
        d.synced.store(true, std::memory_order_release);
      }
      return;
    }
    // (Commands for a device this server does not drive never get here: command_for_us counts them.)
  });
}

void DdsBridge::check_claims() {
  // A claim ends when its claimant's participant is gone: its request writer is no longer matched (a clean exit
  // deletes it; a vanished participant is removed when its lease runs out), or it has no engine command writer
  // whose liveliness holds (a killed or frozen process stops asserting it: the command reader's lease, 0.5 s)
  // once claim_grace_s have passed since the claim.
  const std::int64_t now = steady_ns();
  const auto grace_ns = static_cast<std::int64_t>(settings_.claim_grace_s * 1e9);
  for (auto& dp : devices_) {
    Device& d = *dp;
    PeerId owner;
    dds_instance_handle_t claim_writer = 0;
    std::int64_t claimed_ns = 0;
    {
      std::lock_guard lock(d.mutex);
      if (d.gate.owner().empty()) continue;
      owner = d.gate.owner_participant();
      claim_writer = d.claim_writer;
      claimed_ns = d.claimed_ns;
    }
    const char* why = nullptr;
    if (!PeerDirectory::matched(dds_->request.get(), claim_writer)) {
      why = "left the domain";
    } else if (now - claimed_ns > grace_ns && !dds_->peers.has_live_writer(dds_->command.get(), owner)) {
      why = "has no live command writer (its process died, froze or never had one)";
    }
    if (why == nullptr) continue;
    std::string lost;
    {
      std::lock_guard lock(d.mutex);
      if (!d.gate.owned_by(owner) || d.claimed_ns != claimed_ns) continue;  // released or claimed anew meanwhile
      lost = d.gate.owner();
      d.gate.release_any();
    }
    d.synced.store(false, std::memory_order_release);
    claims_ended_.fetch_add(1, std::memory_order_relaxed);
    send_event(d, hapticd_msg_EVENT_OWNER, "", "engine '" + lost + "' " + why + ": the device is free again");
  }
}

void DdsBridge::check_engine_deadlines() {
  dds_requested_deadline_missed_status_t missed{};
  if (dds_get_requested_deadline_missed_status(dds_->command.get(), &missed) == DDS_RETCODE_OK && missed.total_count_change > 0) {
    for (auto& dp : devices_)
      if (dp->instance.load(std::memory_order_relaxed) == missed.last_instance_handle) dp->deadline_misses.fetch_add(missed.total_count_change);
  }
}

void DdsBridge::handle_requests() {
  dds_->request.take([&](const hapticd_msg_ControlRequest& r, const dds_sample_info_t& info) {
    const std::string_view device = dds::text_of(r.device);
    // The requester is the participant of the writer that sent it, whatever client id the request declares.
    const std::optional<PeerId> requester = dds_->peers.participant_of(dds_->request.get(), info.publication_handle);
    const std::string_view client = dds::text_of(r.client);
    const std::string_view name = dds::text_of(r.name);
    for (auto& dp : devices_) {
      Device& d = *dp;
      if (device != d.session->name()) continue;
      ++d.requests;
      hapticd_msg_ControlReply reply{};
      dds::set_text(reply.device, device);
      dds::set_text(reply.client, client);
      reply.request_id = r.request_id;
      std::string message;
      bool ok = false;
      std::string owner;
      bool may_drive = false;  // free, or claimed by the requester's participant
      {
        std::lock_guard lock(d.mutex);
        owner = d.gate.owner();
        may_drive = owner.empty() || (requester && d.gate.owned_by(*requester));
      }
      const std::vector<double> values(r.values, r.values + std::clamp<std::int32_t>(r.value_count, 0, hapticd_msg_MAX_VALUES));
      if (client.empty() || !dds::terminated(r.client) || !dds::terminated(r.name)) {
        message = "malformed request (no client id)";
      } else if (!requester) {
        message = "request from a writer that is no longer known";
      } else {
        switch (r.kind) {
          case hapticd_msg_REQUEST_CLAIM: {
            std::lock_guard lock(d.mutex);
            ok = d.gate.claim(client, *requester);
            if (ok) {
              d.claim_writer = info.publication_handle;
              d.claimed_ns = steady_ns();
            }
            message = ok ? "claimed" : "claimed by '" + d.gate.owner() + "' (another participant)";
            break;
          }
          case hapticd_msg_REQUEST_RELEASE: {
            std::lock_guard lock(d.mutex);
            ok = d.gate.release(*requester);
            message = ok ? "released" : "not the owner";
            break;
          }
          case hapticd_msg_REQUEST_SWITCH_SCHEME:
            if (!may_drive) {
              message = "claimed by '" + owner + "'";
            } else {
              ok = d.session->request_scheme(name);
              message = ok ? "switching to " + std::string(name) : "no scheme named '" + std::string(name) + "'";
            }
            break;
          case hapticd_msg_REQUEST_SET_PARAMETER:
          case hapticd_msg_REQUEST_OPERATOR: {
            // The simulated operator is the person at the device, not the device: anyone may drive it.
            if (!may_drive && r.kind == hapticd_msg_REQUEST_SET_PARAMETER) {
              message = "claimed by '" + owner + "'";
              break;
            }
            std::string_view stage = "device", parameter = name;
            if (r.kind == hapticd_msg_REQUEST_SET_PARAMETER) {
              const auto dot = name.find('.');
              if (dot == std::string_view::npos) {
                message = "expected <stage>.<parameter>, e.g. virtual_model.mass_kg";
                break;
              }
              stage = name.substr(0, dot);
              parameter = name.substr(dot + 1);
            }
            const std::string request = r.kind == hapticd_msg_REQUEST_OPERATOR ? "operator." + std::string(name) : std::string(parameter);
            const RuntimeReply rr = d.session->handle_request(stage, request, values);
            ok = rr.accepted;
            message = rr.message;
            break;
          }
          case hapticd_msg_REQUEST_ESTOP:
            d.session->request_emergency_stop();  // anyone may stop a device
            ok = true;
            message = "emergency stop";
            break;
          case hapticd_msg_REQUEST_RECOVER: {
            if (!may_drive) {
              message = "claimed by '" + owner + "'";
              break;
            }
            const RuntimeReply rr = d.session->request_recovery();
            ok = rr.accepted;
            message = rr.message;
            break;
          }
          case hapticd_msg_REQUEST_DESCRIBE:
            publish_description(d);
            ok = true;
            message = "description republished";
            break;
          default:
            message = "unknown request kind";
        }
      }
      reply.accepted = ok;
      dds::set_text(reply.message, message);
      (void)dds_->reply.write_once(reply);
      if (ok && (r.kind == hapticd_msg_REQUEST_CLAIM || r.kind == hapticd_msg_REQUEST_RELEASE)) {
        if (r.kind == hapticd_msg_REQUEST_RELEASE) d.synced.store(false, std::memory_order_release);
        send_event(d, hapticd_msg_EVENT_OWNER, r.kind == hapticd_msg_REQUEST_CLAIM ? client : std::string_view(),
                   std::string(client) + (r.kind == hapticd_msg_REQUEST_CLAIM ? " claimed the device" : " released the device"));
      }
      return;
    }
    // (Requests for a device this server does not drive never get here: request_for_us counts them. Another
    // server on the domain may drive it and answers; this one stays silent.)
  });
}

bool DdsBridge::serves(std::string_view device) const noexcept {
  return std::any_of(devices_.begin(), devices_.end(), [&](const auto& d) { return d->session->name() == device; });
}

bool DdsBridge::command_for_us(const void* sample, void* self) {
  auto* bridge = static_cast<DdsBridge*>(self);
  if (bridge->serves(dds::text_of(static_cast<const hapticd_msg_EngineCommand*>(sample)->device))) return true;
  bridge->unknown_device_commands_.fetch_add(1, std::memory_order_relaxed);  // malformed (the IDL's reason 0)
  return false;
}

bool DdsBridge::request_for_us(const void* sample, void* self) {
  auto* bridge = static_cast<DdsBridge*>(self);
  if (bridge->serves(dds::text_of(static_cast<const hapticd_msg_ControlRequest*>(sample)->device))) return true;
  bridge->unknown_device_requests_.fetch_add(1, std::memory_order_relaxed);
  return false;
}

void DdsBridge::publish_telemetry() {
  for (auto& dp : devices_) {
    Device& d = *dp;
    hapticd_msg_Telemetry t{};
    dds::set_text(t.device, d.session->name());
    t.wall_time_ns = dds::wall_clock_ns();
    fill_loop_summary(t.loop);
    t.states_published = d.states.load(std::memory_order_relaxed);
    {
      std::lock_guard lock(d.mutex);
      t.commands_received = d.gate.received();
      t.commands_accepted = d.gate.accepted();
      for (int i = 0; i < dds::kRejectReasons; ++i) t.rejected[i] = d.gate.rejected()[static_cast<std::size_t>(i)];
    }
    t.requests = d.requests;
    t.deadline_misses = d.deadline_misses.load();
    t.scheme_switches = d.session->scheme_switches();
    t.saturated_cycles = d.session->saturated_cycles();
    t.limited_cycles = d.session->limited_cycles();
    t.render_limited_cycles = d.session->render_limited_cycles();
    t.faults = d.session->faults_raised();
    t.recoveries = d.session->recoveries();
    t.thermal_load = d.session->thermal_load();
    t.dissipated_j = d.session->dissipated_j();
    (void)dds_->telemetry.write(t);
  }
}

// ---- queries ----

std::uint64_t DdsBridge::commands_accepted(std::size_t device) const {
  std::lock_guard lock(devices_.at(device)->mutex);
  return devices_[device]->gate.accepted();
}
std::uint64_t DdsBridge::commands_rejected(std::size_t device) const {
  std::lock_guard lock(devices_.at(device)->mutex);
  return devices_[device]->gate.rejected_total();
}
std::array<std::uint64_t, dds::kRejectReasons> DdsBridge::rejected_by_reason(std::size_t device) const {
  std::lock_guard lock(devices_.at(device)->mutex);
  return devices_[device]->gate.rejected();
}
std::string DdsBridge::owner(std::size_t device) const {
  std::lock_guard lock(devices_.at(device)->mutex);
  return devices_[device]->gate.owner();
}
std::uint64_t DdsBridge::deadline_misses(std::size_t device) const { return devices_.at(device)->deadline_misses.load(); }

RoundTripStatistics DdsBridge::round_trip() const {
  LatencyHistogram round_trips;
  RoundTripStatistics counts;
  for (const auto& d : devices_) d->round_trip.merge_into(round_trips, counts);
  return summarise_round_trips(round_trips, counts);
}

}  // namespace hapticd::server
