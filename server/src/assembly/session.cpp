// The in-process session API (hapticd/server/session.hpp).
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "assembly/session_builder.hpp"
#include "assembly/session_impl.hpp"
#include "executor/loop_clock.hpp"
#include "session/device_requests.hpp"

namespace hapticd::server {
namespace {

std::unique_ptr<Session::Impl> build(SessionConfig config, const SessionOptions& options) {
  auto impl = std::make_unique<Session::Impl>();
  impl->config = std::move(config);
  auto& paths = impl->config.server.plugin_paths;
  paths.insert(paths.begin(), options.plugin_paths.begin(), options.plugin_paths.end());
  impl->loader = std::make_unique<PluginLoader>(PluginLoader::search_paths_for(paths));
  impl->devices = build_sessions(impl->config, *impl->loader);
  impl->stages = build_group_stages(impl->config, impl->devices, *impl->loader);
  impl->cycle = std::make_unique<LoopCycle>(impl->device_pointers(), impl->stage_pointers());
  impl->period_ns = static_cast<std::int64_t>(std::llround(1e9 / impl->config.server.rate_hz));
  return impl;
}

double microseconds(std::int64_t ns) { return static_cast<double>(ns) * 1e-3; }

}  // namespace

DeviceSession& Session::Impl::device(std::string_view name) const {
  for (const auto& d : devices)
    if (d->name() == name) return *d;
  throw std::out_of_range("the session has no device '" + std::string(name) + "'");
}

std::vector<DeviceSession*> Session::Impl::device_pointers() const {
  std::vector<DeviceSession*> out;
  for (const auto& d : devices) out.push_back(d.get());
  return out;
}

std::vector<GroupStage*> Session::Impl::stage_pointers() const {
  std::vector<GroupStage*> out;
  for (const auto& g : stages) out.push_back(g.get());
  return out;
}

ExecutorSettings Session::Impl::executor_settings() const {
  ExecutorSettings s;
  s.rate_hz = config.server.rate_hz;
  s.lockstep = config.server.clock == ClockMode::lockstep;
  s.duration_s = config.server.duration_s;
  s.shutdown_ramp_s = config.server.shutdown_ramp_s;
  s.realtime_priority = 0;
  s.lock_memory = false;
  if (const ClockDevice clock = clock_device(config, device_pointers()); clock.device != nullptr)
    s.device_clock_stall_ns = std::llround(clock.stall_s * 1e9);
  return s;
}

LoopPlan Session::Impl::loop_plan(DeviceCycleSink* sink) const {
  return LoopPlan(device_pointers(), stage_pointers(), {}, config.server.clock == ClockMode::lockstep, -1, sink,
                  clock_device(config, device_pointers()).device);
}

Session Session::from_file(const std::filesystem::path& file, const SessionOptions& options) {
  return Session(build(load_session_config(file, options.overrides), options));
}

Session Session::from_yaml(const std::string& yaml, const SessionOptions& options, const std::string& name) {
  return Session(build(parse_session_config(yaml, name, options.overrides), options));
}

Session::Session(std::unique_ptr<Impl> impl) noexcept : impl_(std::move(impl)) {}
Session::Session(Session&&) noexcept = default;
Session& Session::operator=(Session&& other) noexcept {
  if (this != &other) {
    if (impl_) stop();
    impl_ = std::move(other.impl_);
  }
  return *this;
}
Session::~Session() {
  if (!impl_) return;
  try {
    stop();
  } catch (...) {  // a device whose disable() threw: every device was still disabled; a destructor cannot report
  }
}

std::vector<std::string> Session::device_names() const {
  std::vector<std::string> names;
  for (const auto& d : impl_->devices) names.push_back(d->name());
  return names;
}

double Session::period_s() const noexcept { return static_cast<double>(impl_->period_ns) * 1e-9; }
std::uint64_t Session::cycles_run() const noexcept { return impl_->next_cycle; }

void Session::step(std::uint64_t cycles) {
  Impl& s = *impl_;
  if (s.stopped) throw std::logic_error("the session has stopped");
  if (!s.activated) {
    // A device that cannot be enabled or homed is held in its safe state; the others run.
    for (const auto& d : s.devices) d->activate();
    s.activated = true;
  }
  for (std::uint64_t k = 0; k < cycles; ++k) {
    const std::uint64_t index = s.next_cycle++;
    const std::int64_t start_ns = monotonic_now_ns();
    s.cycle->run_cycle(CycleTime{static_cast<std::int64_t>(index) * s.period_ns, s.period_ns, index}, 1.0, 0, 0);
    s.statistics.record(0, monotonic_now_ns() - start_ns, false);
    if (k % 64 == 63) s.service_devices();  // as the server's monitor does every 20 ms
  }
  s.service_devices();
}

DeviceDescription Session::description(std::string_view name) const { return impl_->device(name).description(); }

DeviceView Session::device(std::string_view name) const {
  const DeviceSession& d = impl_->device(name);
  DeviceView v;
  v.name = d.name();
  v.cycle = impl_->next_cycle == 0 ? 0 : impl_->next_cycle - 1;
  v.time_s = static_cast<double>(v.cycle) * period_s();
  v.state = d.state();
  const ChainState& chain = d.chain_state();
  v.handle_pose = chain.handle_pose;
  v.handle_twist = chain.handle_twist;
  v.operator_wrench = chain.operator_wrench;
  v.task = d.task();
  v.command = d.command();
  v.scheme = d.schemes().active_name();
  v.fault = d.status().fault_text();
  v.at_rest = d.status().at_rest();
  v.engine_weight = d.engine_weight();
  v.faults = d.status().faults_raised();
  v.recoveries = d.status().recoveries();
  v.scheme_switches = d.schemes().switches();
  v.refused_switches = d.schemes().refused();
  v.saturated_cycles = d.status().saturated_cycles();
  v.limited_cycles = d.status().limited_cycles();
  v.render_limited_cycles = d.status().render_limited_cycles();
  v.thermal_load = d.status().thermal_load();
  v.dissipated_j = d.status().dissipated_j();
  if (SimulatedTruth truth; d.chain().device->simulated_truth(truth)) v.truth = truth;
  return v;
}

void Session::set_engine_input(std::string_view device, const EngineInput& input) {
  impl_->device(device).requests().engine_input(input);
}

RuntimeReply Session::request(std::string_view device, const DeviceRequest& request) {
  return impl_->device(device).requests().apply(request);
}

SessionStatistics Session::statistics() const {
  const CycleStatistics& c = impl_->statistics;
  SessionStatistics s;
  s.cycles = c.cycles;
  s.time_s = static_cast<double>(impl_->next_cycle) * period_s();
  if (c.cycles > 0) {
    s.compute_p50_us = microseconds(c.compute_time.quantile_ns(0.5));
    s.compute_p99_us = microseconds(c.compute_time.quantile_ns(0.99));
    s.compute_max_us = microseconds(c.compute_time.max_ns());
  }
  return s;
}

void Session::stop() {
  Impl& s = *impl_;
  if (s.stopped) return;
  s.stopped = true;
  if (!s.activated) return;
  // As a run of its duration ends: a linear ramp from 1 to 0, the last cycle commands exactly zero.
  const auto ramp = std::max<std::uint64_t>(
      1, static_cast<std::uint64_t>(std::llround(s.config.server.shutdown_ramp_s * s.config.server.rate_hz)));
  for (std::uint64_t k = 1; k <= ramp; ++k) {
    const std::uint64_t index = s.next_cycle++;
    const double scale = std::max(0.0, 1.0 - static_cast<double>(k) / static_cast<double>(ramp));
    s.cycle->run_cycle(CycleTime{static_cast<std::int64_t>(index) * s.period_ns, s.period_ns, index}, scale, 0, 0);
  }
  for (const auto& g : s.stages)
    if (std::string error = g->deactivate(); !error.empty())
      s.plugin_errors.push_back("group '" + g->name() + "': " + error);
  std::string failed;
  for (const auto& d : s.devices) {
    d->deactivate();  // every device, whatever another one's plugins or disable() did
    if (!d->disable_error().empty()) failed += (failed.empty() ? "" : "; ") + d->name() + ": " + d->disable_error();
  }
  s.service_devices();  // what the last deactivation threw
  std::string message;
  if (!failed.empty()) message = "devices not disabled cleanly: " + failed;
  for (const std::string& e : s.plugin_errors)
    message += (message.empty() ? "plugins failed as they were deactivated: " : "; ") + e;
  if (!message.empty()) throw std::runtime_error(message);
}

void Session::Impl::service_devices() {
  for (const auto& d : devices) {
    d->service();
    for (std::string& e : d->take_plugin_errors()) plugin_errors.push_back("device '" + d->name() + "': " + e);
  }
}

}  // namespace hapticd::server
