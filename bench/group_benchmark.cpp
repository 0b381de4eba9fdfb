// Compute time of the group stage (phase (b)) for two devices of a shipped dual-arm session: one iteration is
// one cycle's collision guard - both arms' capsules placed, every pair of capsules measured, the nearest
// neighbour and its clearance gradients handed to both devices, and (in the `repelling` variant, with the
// repulsion's distance wide enough that every pair is inside it) each pair's repulsion and both handle forces.
// The state is the session's after 1 s in lockstep. Side by side, the reference the other benchmarks divide by:
// the per-cycle model terms of the first device (ratio_to_model_terms).
#include <benchmark/benchmark.h>

#include <chrono>
#include <string>

#include "group/group_stage.hpp"
#include "session_rig.hpp"

namespace {

using namespace hapticd;

void group_stage(benchmark::State& st, const std::string& session_file, double repulsion_distance_m) {
  server::Session session = server::Session::from_file(
      std::string(HAPTICD_SOURCE_DIR) + "/config/sessions/dual-arm/" + session_file, {{}, {HAPTICD_PLUGIN_DIR}});
  session.step(2000);
  auto& devices = session.impl().devices;
  server::RepulsionSettings repulsion;
  repulsion.distance_m = repulsion_distance_m;
  server::GroupStage stage("bench", {devices.at(0).get(), devices.at(1).get()}, 0.0, repulsion,
                           1.0 / session.impl().config.server.rate_hz);
  std::uint64_t k = 2000;
  const auto one_cycle = [&] {
    stage.run(CycleTime{static_cast<std::int64_t>(k) * 500'000, 500'000, k});
    ++k;
  };
  for (auto _ : st) one_cycle();
  constexpr int kRuns = 20000;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < kRuns; ++i) one_cycle();
  const double own = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / kRuns;
  const server::DeviceSession& first = *devices.at(0);
  const double reference = bench::seconds_per_model_terms(first.chain_state(), first.state());
  st.counters["pairs"] = static_cast<double>(first.chain().robot_model->collision().size() *
                                             devices.at(1)->chain().robot_model->collision().size());
  st.counters["model_terms_us"] = reference * 1e6;
  st.counters["ratio_to_model_terms"] = own / reference;
}

}  // namespace

BENCHMARK_CAPTURE(group_stage, vishard10_station_measuring, std::string("vishard10-station.yaml"), 0.0)
    ->Name("group/vishard10-station/measuring")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(group_stage, vishard10_station_repelling, std::string("vishard10-station.yaml"), 1.0)
    ->Name("group/vishard10-station/repelling")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(group_stage, vishard3_pair_measuring, std::string("vishard3-pair.yaml"), 0.0)
    ->Name("group/vishard3-pair/measuring")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
