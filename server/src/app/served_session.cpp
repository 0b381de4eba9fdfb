#include "app/served_session.hpp"

#include <algorithm>
#include <cmath>
#include <thread>

#include "app/invariant_stop.hpp"
#include "assembly/session_builder.hpp"
#include "group/group_stage.hpp"
#include "hapticd/input_file.hpp"

namespace hapticd::server {
namespace {

ExecutorSettings executor_settings(const ServerSettings& server, bool realtime_setup) {
  ExecutorSettings s;
  s.rate_hz = server.rate_hz;
  s.lockstep = server.clock == ClockMode::lockstep;
  s.duration_s = server.duration_s;
  s.shutdown_ramp_s = server.shutdown_ramp_s;
  s.realtime_priority = realtime_setup ? server.realtime_priority : 0;
  s.lock_memory = realtime_setup && server.lock_memory;
  s.cpu = realtime_setup ? server.cpu : -1;
  // The limit keeps every CPU of the machine out of deep idle states: worth it for a loop on SCHED_FIFO only.
  s.cpu_dma_latency_us = realtime_setup && server.realtime_priority > 0 ? server.cpu_dma_latency_us : -1;
  return s;
}

// The groups that run on a loop of their own (`groups[i].loop`), with their devices as built.
std::vector<SeparateLoop> separate_loops(const SessionConfig& config, const std::vector<GroupStage*>& stages,
                                         bool realtime_setup) {
  std::vector<SeparateLoop> loops;
  for (const GroupConfig& g : config.groups) {
    if (!g.own_loop) continue;
    for (const GroupStage* stage : stages)
      if (stage->name() == g.name)
        loops.push_back(SeparateLoop{g.name, stage->devices(), realtime_setup ? g.loop_cpu : -1});
  }
  return loops;
}

// Where the DDS threads run (docs/dds-interface.md, "CPUs"); may pin the session's loop too (auto: the last CPU
// no group's loop is pinned to). Auto keeps the DDS threads off every loop's CPU; when the loops take every CPU
// the DDS threads are not pinned.
std::vector<int> dds_cpus_for(const DdsSettings& dds, bool realtime_setup, ExecutorSettings& settings,
                              const std::vector<SeparateLoop>& separate) {
  std::vector<int> cpus;
  if (!dds.enabled || !realtime_setup) return cpus;
  const int n = static_cast<int>(std::thread::hardware_concurrency());
  if (dds.cpu >= 0) {
    cpus = {dds.cpu};
  } else if (dds.cpu == -2 && !settings.lockstep && n >= 2) {
    const auto taken = [&](int c) {
      return c == settings.cpu ||
             std::any_of(separate.begin(), separate.end(), [c](const SeparateLoop& l) { return l.cpu == c; });
    };
    for (int c = n - 1; c >= 0 && settings.cpu < 0; --c)
      if (!taken(c)) settings.cpu = c;
    for (int c = 0; c < n; ++c)
      if (!taken(c)) cpus.push_back(c);
  }
  return cpus;
}

}  // namespace

// What the recording says of the session before its first cycle.
RecordingHeader recording_header(const SessionConfig& config, const std::vector<DeviceSession*>& devices) {
  RecordingHeader h;
  h.session_file = config.file.string();
  if (!config.file.empty()) {
    try {  // the file the session was read from (hapticd/input_file.hpp: a regular file, size-limited)
      h.session_text = read_input_file(config.file, "session file");
    } catch (const std::runtime_error&) {
      h.session_text.clear();  // gone or changed since: the recording says nothing of its text
    }
  }
  h.rate_hz = config.server.rate_hz;
  h.lockstep = config.server.clock == ClockMode::lockstep;
  for (const DeviceSession* d : devices) {
    RecordingDevice rd{d->name(), d->description(), {}};
    for (const SchemeChain& s : d->chain().schemes) rd.schemes.push_back(s.name);
    h.devices.push_back(std::move(rd));
  }
  return h;
}

ServedSession::ServedSession(const SessionConfig& config, const std::vector<DeviceSession*>& devices,
                             std::vector<GroupStage*> stages, const ServeOptions& options)
    : settings_(executor_settings(config.server, options.realtime_setup)) {
  const std::vector<SeparateLoop> separate = separate_loops(config, stages, options.realtime_setup);
  dds_cpus_ = dds_cpus_for(config.dds, options.realtime_setup, settings_, separate);
  if (!options.record_file.empty()) {
    recorder_ = std::make_unique<Recorder>(options.record_file, recording_header(config, devices), settings_.lockstep,
                                           LoopPlan::count(separate, settings_.lockstep));
  }
  const ClockDevice clock = clock_device(config, devices);
  if (clock.device != nullptr) settings_.device_clock_stall_ns = std::llround(clock.stall_s * 1e9);
  loops_ = std::make_unique<LoopPlan>(devices, stages, separate, settings_.lockstep, settings_.cpu, recorder_.get(),
                                      clock.device);
  executor_ = std::make_unique<Executor>(settings_, loops_->loops());
  if (config.live_view.enabled)  // binds its port before the DDS interface starts
    live_view_ = std::make_unique<live_view::LiveView>(
        config.live_view, devices, config.server.rate_hz, config.file.filename().string(),
        !devices.empty() && devices.front()->chain().scene ? devices.front()->chain().scene->object.get() : nullptr);
  if (config.teleoperation.enabled)  // the device's side of the link runs in its cycle; the doors carry its packets
    for (DeviceSession* d : devices)
      if (d->name() == config.teleoperation.device)
        d->enable_teleoperation(config.teleoperation.role, config.teleoperation.link);
  if (config.dds.enabled || config.engine_socket.enabled || config.ros2.enabled) {  // the gate and its doors
    doors_ = std::make_unique<Doors>(config, devices, stages, dds_cpus_);
    for (std::size_t d = 0; d < devices.size(); ++d)
      doors_->set_loop_statistics(d, &executor_->live(loops_->loop_of(devices[d])));
    if (live_view_) {  // the engines' worlds, drawn beside the devices
      live_view::LiveView* view = live_view_.get();
      doors_->relay_worlds([view](const hapticd_msg_World& w) { view->take_world(w); });
    }
    set_cycle_listener(doors_.get());
    doors_->start();
  }
  if (live_view_) live_view_->start();
  monitor_ = std::make_unique<SessionMonitor>(devices, doors_.get(), options.stop, recorder_.get());
}

ServedSession::~ServedSession() {
  if (live_view_) live_view_->stop();
  if (doors_) doors_->stop();
}

void ServedSession::set_cycle_listener(CycleListener* listener) {
  listener_ = listener;
  executor_->set_cycle_listener(listener);
}

ExecutorResult ServedSession::run(const std::atomic<bool>& stop) {
  struct Finish {  // however the loop ends
    ServedSession& s;
    ~Finish() {
      if (s.recorder_) {
        s.recorder_->finish();  // the summary and the close follow (close_recording)
        s.monitor_->poll();     // a failure at the end (the last chunk, the sync, the close) is announced too
      }
      // After a broken invariant one of their threads is parked in the handler (app/invariant_stop): joining it
      // would hang; the process ends with exit code 4 without them.
      if (invariant_failure()) return;
      if (s.live_view_) s.live_view_->stop();
      if (s.doors_) s.doors_->stop();
    }
  } finish{*this};
  return executor_->run(stop, [this] { monitor_->poll(); });
}

}  // namespace hapticd::server
