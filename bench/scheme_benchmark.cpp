// Compute time per cycle of each control scheme on the simulated ViSHaRD3 and ViSHaRD6: one iteration runs the
// scheme's chain (virtual model -> inverse kinematics -> controller) on a realistic state, taken after 1 s of
// the shipped session (config/sessions/<device>/<scheme>.yaml) in lockstep, with the server's render guard (as the
// loop configures it without passivity control) as the model's render port. Side by side, the reference: the
// server's shared per-cycle model terms (compute_cycle_terms) for the same device; the counter
// ratio_to_model_terms is the scheme's time over the reference's (machine-independent to first order).
#include <benchmark/benchmark.h>

#include <chrono>
#include <map>
#include <memory>
#include <string>

#include "assembly/session_builder.hpp"
#include "config/session_config.hpp"
#include "hapticd/chain_state.hpp"
#include "hapticd/engine_input.hpp"
#include "hapticd/model/dynamics.hpp"
#include "hapticd/model/model_data.hpp"
#include "loader/plugin_loader.hpp"
#include "safety/render_guard.hpp"
#include "session_rig.hpp"

namespace {

using namespace hapticd;
using bench::seconds_per_model_terms;

void scheme(benchmark::State& st, const std::string& device, const std::string& scheme_file) {
  server::Session session = bench::run_shipped_session(device, scheme_file);
  server::DeviceSession& d = bench::first_device(session);
  const server::SchemeChain& chain = d.chain().schemes[0];
  const ChainState cs = d.chain_state();
  const DeviceState state = d.state();
  const EngineInput engine;
  server::RenderGuard render;  // as the server's: configured for the period, default limits, passivity control off
  render.configure(5e-4, server::RenderLimits{}, false, 0.0, 0.0);
  TaskTarget task;
  JointTarget joints;
  joints.resize(d.description().dof());
  JointCommand command;
  command.torque_nm = d.command().torque_nm;
  std::uint64_t k = 2000;
  const auto one_cycle = [&] {
    const CycleTime t{static_cast<std::int64_t>(k) * 500'000, 500'000, k};
    ++k;
    render.begin_cycle(Eigen::Vector3d::Zero());
    if (chain.virtual_model)
      (void)(*chain.virtual_model)->update(t, VirtualModelInput{state, cs, engine, render}, task);
    if (chain.inverse_kinematics)
      (void)(*chain.inverse_kinematics)->update(t, InverseKinematicsInput{state, task, cs}, joints);
    (void)chain.controller->update(t, ControllerInput{state, task, joints, cs, nullptr}, command);
    benchmark::DoNotOptimize(command.torque_nm.data());
  };
  for (auto _ : st) one_cycle();
  // Side by side: the scheme and the reference timed back to back outside the framework, for the ratio.
  constexpr int kRuns = 20000;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < kRuns; ++i) one_cycle();
  const double own = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / kRuns;
  const double reference = seconds_per_model_terms(cs, state);
  st.counters["model_terms_us"] = reference * 1e6;
  st.counters["ratio_to_model_terms"] = own / reference;
}

const char* kSchemes[] = {"impedance-open-loop",
                          "impedance-force-feedback",
                          "impedance-friction-compensation",
                          "impedance-stiction",
                          "impedance-adaptive-friction",
                          "impedance-disturbance-observer",
                          "impedance-joint-torque-feedback",
                          "admittance-resolved-acceleration",
                          "admittance-inverse-jacobian",
                          "admittance-transposed-jacobian",
                          "admittance-computed-torque",
                          "admittance-joint-pd",
                          "admittance-motion-based",
                          "admittance-virtual-coupling"};

const bool kRegistered = [] {
  for (const char* device : {"vishard3", "vishard6"}) {
    for (const char* s : kSchemes) {
      benchmark::RegisterBenchmark((std::string("scheme/") + device + "/" + s).c_str(), [device,
                                                                                         s](benchmark::State& st) {
        scheme(st, device, s);
      })->Unit(benchmark::kMicrosecond);
    }
  }
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
