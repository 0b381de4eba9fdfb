#include "gate/state_fanout.hpp"

#include <algorithm>

#include "executor/loop_clock.hpp"
#include "hapticd/dds/conversion.hpp"
#include "session/device_requests.hpp"

namespace hapticd::server {

StateFanout::StateFanout(DeviceGates& devices, EventFanout& events, double rate_hz, std::uint64_t snapshot_interval)
    : devices_(devices),
      events_(events),
      rate_hz_(rate_hz),
      snapshot_interval_(snapshot_interval),
      live_(devices.size(), nullptr),
      published_(devices.size()),
      group_snapshot_(std::make_unique<GroupSnapshot>()),
      group_written_ns_(devices.groups().size(), 0) {
  for (std::size_t i = 0; i < devices.groups().size(); ++i)
    group_messages_.push_back(std::make_unique<hapticd_msg_GroupState>());
  for (std::size_t i = 0; i < devices.size(); ++i)
    for (const SchemeChain& s : devices[i].device->chain().schemes) published_[i].scheme_names.push_back(s.name);
}

hapticd_msg_LoopSummary StateFanout::loop_summary(std::size_t device) const noexcept {
  hapticd_msg_LoopSummary loop{};
  loop.rate_hz = rate_hz_;
  const LiveLoopStatistics* live = live_[device];
  if (live == nullptr) return loop;
  loop.cycles = live->cycles.load(std::memory_order_relaxed);
  loop.overruns = live->overruns.load(std::memory_order_relaxed);
  loop.latency_max_us = static_cast<double>(live->window_latency_max_ns.load(std::memory_order_relaxed)) * 1e-3;
  loop.compute_max_us = static_cast<double>(live->window_compute_max_ns.load(std::memory_order_relaxed)) * 1e-3;
  return loop;
}

void StateFanout::publish_states() {
  for (std::size_t i = 0; i < devices_.size(); ++i) {
    DeviceGate& d = devices_[i];
    Published& p = published_[i];
    if (!d.status->take_snapshot(p.snapshot)) {
      // Nothing new (the loop waits, e.g. for the first engine in lockstep): repeat the last state now and
      // then, for readers that matched after it was written.
      if (d.states.load(std::memory_order_relaxed) > 0 && monotonic_now_ns() - p.last_write_ns > 10'000'000) {
        for (Door* door : doors_) door->repeat_state(p.last);
        p.last_write_ns = monotonic_now_ns();
      }
      continue;
    }
    const DeviceSnapshot& s = p.snapshot;
    bool first = false;
    {
      std::lock_guard lock(description_mutex_);
      if (!p.start_pose) {
        p.start_pose = s.handle_pose;
        first = true;
      }
    }
    if (first) publish_description(i);  // now with the start pose
    std::string owner;
    {
      std::lock_guard lock(d.mutex);
      owner = d.gate.owner();
    }
    p.last = state_message(s, labels_of(i, s, owner));
    d.round_trip.command_applied(s.engine_sequence, s.cycle);
    d.round_trip.state_written(p.last.serial, s.cycle, monotonic_now_ns());
    for (Door* door : doors_) door->state(i, s, p.last);
    d.states.fetch_add(1, std::memory_order_relaxed);
    d.loop_time_ns.store(s.time_ns, std::memory_order_relaxed);
    p.last_write_ns = monotonic_now_ns();

    const PublishedView now = view_of(s);
    for (const EventText& e : events_between(p.view, now, p.scheme_names)) events_.send(d, e.kind, e.code, e.message);
    p.view = now;
  }
  publish_group_states();
}

StateLabels StateFanout::labels_of(std::size_t device, const DeviceSnapshot& s, const std::string& owner) const {
  const DeviceRequests& session = *devices_[device].device;
  return StateLabels{session.name(), s.cycle / snapshot_interval_ + 1, session.schemes().active_name(), owner,
                     loop_summary(device)};
}

void StateFanout::publish_group_states() {
  GroupSnapshot& g = *group_snapshot_;
  for (std::size_t i = 0; i < devices_.groups().size(); ++i) {
    GroupGate& group = devices_.groups()[i];
    hapticd_msg_GroupState& m = *group_messages_[i];
    if (!group.stage->take_snapshot(g)) {
      // Nothing new (the loop waits, e.g. for the engines in lockstep): repeat the last one now and then, for
      // readers that matched, or set their callback, after it was written.
      if (group.serial > 0 && monotonic_now_ns() - group_written_ns_[i] > 10'000'000) {
        for (Door* door : doors_) door->group_state(m, true);
        group_written_ns_[i] = monotonic_now_ns();
      }
      continue;
    }
    m = hapticd_msg_GroupState{};
    dds::set_text(m.group, group.name);
    m.serial = ++group.serial;
    m.cycle = g.cycle;
    m.loop_time_ns = g.time_ns;
    m.clearance_m = g.clearance_m;
    m.device_count = static_cast<std::int32_t>(std::min(g.count, group.members.size()));
    for (std::size_t k = 0; k < static_cast<std::size_t>(m.device_count); ++k) {
      DeviceGate& d = devices_[group.members[k]];
      std::string owner;
      {
        std::lock_guard lock(d.mutex);
        owner = d.gate.owner();
      }
      m.states[k] = state_message(g.devices[k], labels_of(d.index, g.devices[k], owner));
    }
    for (Door* door : doors_) door->group_state(m, false);
    group_written_ns_[i] = monotonic_now_ns();
  }
}

void StateFanout::publish_group_description(const GroupGate& group) {
  hapticd_msg_GroupDescription m{};
  dds::set_text(m.group, group.name);
  m.data_model_version = hapticd_msg_VERSION;
  m.device_count = static_cast<std::int32_t>(group.members.size());
  for (std::size_t k = 0; k < group.members.size(); ++k)
    dds::set_text(m.devices[k].text, devices_[group.members[k]].device->name());
  m.min_distance_m = group.stage->min_distance_m();
  m.repulsion_distance_m = group.stage->repulsion_distance_m();
  m.own_loop = group.stage->own_loop();
  for (Door* door : doors_) door->group_description(m);
}

void StateFanout::publish_description(std::size_t device) {
  std::optional<Pose> start;
  {
    std::lock_guard lock(description_mutex_);
    start = published_[device].start_pose;
  }
  const hapticd_msg_DeviceDescription m = description_message(*devices_[device].device, rate_hz_, start);
  for (Door* door : doors_) door->description(m);
}

void StateFanout::publish_fault_report(std::size_t device, const FaultReport& report) {
  const DeviceRequests& s = *devices_[device].device;
  auto m = std::make_unique<hapticd_msg_FaultReport>();  // 100 kB: not on the stack
  fill_fault_report(*m, s.name(), s.description().dof(), report);
  for (Door* door : doors_) door->fault_report(*m);
}

void StateFanout::publish_telemetry() {
  for (std::size_t i = 0; i < devices_.size(); ++i) {
    const DeviceGate& d = devices_[i];
    hapticd_msg_Telemetry t{};
    dds::set_text(t.device, d.device->name());
    t.wall_time_ns = dds::wall_clock_ns();
    t.loop = loop_summary(i);
    t.states_published = d.states.load(std::memory_order_relaxed);
    {
      std::lock_guard lock(d.mutex);
      t.commands_received = d.gate.received();
      t.commands_accepted = d.gate.accepted();
      for (int r = 0; r < dds::kRejectReasons; ++r) t.rejected[r] = d.gate.rejected()[static_cast<std::size_t>(r)];
    }
    t.requests = d.requests.load(std::memory_order_relaxed);
    // (deadline_misses: the DDS door's count, filled in by it)
    t.scheme_switches = d.device->schemes().switches();
    t.saturated_cycles = d.device->status().saturated_cycles();
    t.limited_cycles = d.device->status().limited_cycles();
    t.render_limited_cycles = d.device->status().render_limited_cycles();
    t.faults = d.device->status().faults_raised();
    t.recoveries = d.device->status().recoveries();
    t.thermal_load = d.device->status().thermal_load();
    t.dissipated_j = d.device->status().dissipated_j();
    for (Door* door : doors_) door->telemetry(t);
  }
}

}  // namespace hapticd::server
