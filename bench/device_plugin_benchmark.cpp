// Each commercial device plugin's own time per cycle - read() then write(), what the loop calls of a device - on
// the project's stand-ins of the vendors' SDKs and service (tests/standins): Force Dimension's libdhd (each call
// into the stand-in library), OpenHaptics' libHD (the servo callback runs on the stand-in's scheduler thread; the
// loop's side takes its sample and hands over the force), Haply's Inverse Service (the I/O thread exchanges the
// messages; the loop's side as for OpenHaptics). Side by side, the reference: the same calls on the simulated
// ViSHaRD3 (one period of its physics), the counter sim_ns. The vendors' own libraries and service would add their
// time: not measured here (no hardware).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdlib>
#include <string>

#include "assembly/session_impl.hpp"
#include "hapticd/server/session.hpp"
#include "inverse_service_standin.hpp"

namespace {

using namespace hapticd;

std::string session_file(const std::string& relative) {
  return std::string(HAPTICD_SOURCE_DIR) + "/config/sessions/" + relative;
}

// Seconds per read() + write() on the session's first device, over `st`'s iterations.
void time_device(benchmark::State& st, server::Session& s) {
  server::DeviceSession& d = *s.impl().devices.at(0);
  Device& device = *d.chain().device.operator->();
  DeviceState state = d.state();
  JointCommand command = d.command();
  CycleTime cycle{0, 1'000'000, 0};
  for (auto _ : st) {
    ++cycle.index;
    cycle.time_ns += cycle.period_ns;
    benchmark::DoNotOptimize(device.read(cycle, state));
    benchmark::DoNotOptimize(device.write(cycle, command));
  }
}

double sim_seconds() {
  static const double seconds = [] {
    server::Session s =
        server::Session::from_file(session_file("vishard3/impedance-force-feedback.yaml"), {{}, {HAPTICD_PLUGIN_DIR}});
    s.step(100);
    server::DeviceSession& d = *s.impl().devices.at(0);
    Device& device = *d.chain().device.operator->();
    DeviceState state = d.state();
    const JointCommand command = d.command();
    CycleTime cycle{s.impl().period_ns * 100, s.impl().period_ns, 100};
    constexpr int kRuns = 20000;
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < kRuns; ++i) {
      ++cycle.index;
      cycle.time_ns += cycle.period_ns;
      (void)device.read(cycle, state);
      (void)device.write(cycle, command);
    }
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / kRuns;
  }();
  return seconds;
}

// The reference beside each: the simulated ViSHaRD3's read() + write() [ns].
void report(benchmark::State& st) { st.counters["sim_ns"] = sim_seconds() * 1e9; }

void ForceDimension(benchmark::State& st) {
  ::setenv("FORCEDIM_SDK", HAPTICD_STANDIN_DIR "/forcedimension", 1);
  server::Session s =
      server::Session::from_file(session_file("forcedimension/omega-wall.yaml"), {{}, {HAPTICD_PLUGIN_DIR}});
  s.step(10);
  time_device(st, s);
  report(st);
}

void OpenHaptics(benchmark::State& st) {
  ::setenv("OH_SDK_BASE", HAPTICD_STANDIN_DIR "/openhaptics", 1);
  server::Session s =
      server::Session::from_file(session_file("openhaptics/touch-wall.yaml"), {{}, {HAPTICD_PLUGIN_DIR}});
  s.step(10);  // enabled: the scheduler calls back, samples to take
  time_device(st, s);
  report(st);
}

void Haply(benchmark::State& st) {
  standins::InverseServiceStandIn service({});
  server::Session s =
      server::Session::from_file(session_file("haply/inverse3-wall.yaml"),
                                 {{"devices.inverse3.device.parameters.url=" + service.url()}, {HAPTICD_PLUGIN_DIR}});
  s.step(10);  // enabled: the I/O thread exchanges messages
  time_device(st, s);
  report(st);
}

}  // namespace

BENCHMARK(ForceDimension);
BENCHMARK(OpenHaptics);
BENCHMARK(Haply);
BENCHMARK_MAIN();
