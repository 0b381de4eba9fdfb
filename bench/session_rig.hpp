#pragma once
// A shipped session (config/sessions/<device>/<scheme>.yaml) built with the in-process session API and run for
// 1 s in lockstep, so a benchmark times its chain on a realistic state; and the reference the benchmarks divide
// by: the server's shared per-cycle model terms (compute_cycle_terms) for the same device.
#include <benchmark/benchmark.h>

#include <chrono>
#include <string>

#include "assembly/session_impl.hpp"
#include "hapticd/chain_state.hpp"
#include "hapticd/model/dynamics.hpp"
#include "hapticd/model/model_data.hpp"
#include "hapticd/server/session.hpp"

namespace hapticd::bench {

inline server::Session run_shipped_session(const std::string& device, const std::string& scheme) {
  server::Session s = server::Session::from_file(
      std::string(HAPTICD_SOURCE_DIR) + "/config/sessions/" + device + "/" + scheme + ".yaml",
      {{}, {HAPTICD_PLUGIN_DIR}});
  s.step(2000);
  return s;
}

// The session's first device, whose plugins a benchmark times one by one.
inline server::DeviceSession& first_device(server::Session& s) { return *s.impl().devices.at(0); }

inline double seconds_per_model_terms(const ChainState& chain, const DeviceState& state) {
  model::ModelData data(*chain.model);
  const auto start = std::chrono::steady_clock::now();
  constexpr int kRuns = 20000;
  for (int i = 0; i < kRuns; ++i) {
    model::compute_cycle_terms(*chain.model, data, state.joints.position, state.joints.velocity, chain.handle_frame);
    benchmark::DoNotOptimize(data.mass_matrix.data());
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / kRuns;
}

}  // namespace hapticd::bench
