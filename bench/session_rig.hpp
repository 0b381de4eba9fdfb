#pragma once
// A shipped session (config/sessions/<device>/<scheme>.yaml) built and run for 1 s in lockstep, so a benchmark
// times its chain on a realistic state; and the reference the benchmarks divide by: the server's shared per-cycle
// model terms (compute_cycle_terms) for the same device.
#include <benchmark/benchmark.h>

#include <chrono>
#include <memory>
#include <string>

#include "config/session_config.hpp"
#include "hapticd/chain_state.hpp"
#include "hapticd/model/dynamics.hpp"
#include "hapticd/model/model_data.hpp"
#include "plugins/plugin_loader.hpp"
#include "session/session_builder.hpp"

namespace hapticd::bench {

struct Rig {
  server::SessionConfig config;
  std::unique_ptr<server::PluginLoader> loader;
  std::vector<std::unique_ptr<server::DeviceSession>> sessions;
};

inline std::unique_ptr<Rig> make_rig(const std::string& device, const std::string& scheme) {
  auto rig = std::make_unique<Rig>();
  rig->config = server::load_session_config(std::string(HAPTICD_SOURCE_DIR) + "/config/sessions/" + device + "/" +
                                            scheme + ".yaml");
  rig->config.server.plugin_paths.push_back(HAPTICD_PLUGIN_DIR);
  rig->loader = std::make_unique<server::PluginLoader>(rig->config.server.plugin_paths);
  rig->sessions = server::build_sessions(rig->config, *rig->loader);
  server::DeviceSession& d = *rig->sessions[0];
  d.activate();
  const std::int64_t period = 500'000;
  for (std::uint64_t k = 0; k < 2000; ++k) d.cycle(CycleTime{static_cast<std::int64_t>(k) * period, period, k}, 1.0);
  return rig;
}

inline double seconds_per_model_terms(const ChainState& chain, const DeviceState& state) {
  model::ModelData data(*chain.model);
  const auto start = std::chrono::steady_clock::now();
  constexpr int kRuns = 20000;
  for (int i = 0; i < kRuns; ++i) {
    model::compute_cycle_terms(*chain.model, data, state.joints.position, chain.velocity, chain.handle_frame);
    benchmark::DoNotOptimize(data.mass_matrix.data());
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / kRuns;
}

}  // namespace hapticd::bench
