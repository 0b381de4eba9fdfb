// Compute time per cycle of each redundancy resolution on the simulated ViSHaRD10 (10 joints, 6-D task): the
// shipped sessions config/sessions/vishard10/*.yaml after 1 s in lockstep. Two figures per session: the
// inverse kinematics' update alone (ik/...), and the whole resolution (resolution/...: the server's model terms,
// virtual model, IK, controller - the task-space controllers call the IK's resolution at the measured state, so
// part of its cost shows only here). The counter ratio_to_model_terms divides by the server's per-cycle model
// terms for the same state, timed side by side (machine-independent to first order); issue 23's goal is a
// resolution of at most 5 us or at most 2 model terms.
#include <benchmark/benchmark.h>

#include <chrono>
#include <string>

#include "hapticd/engine_input.hpp"
#include "hapticd/testing/pass_through_render_port.hpp"
#include "session_rig.hpp"

namespace {

using namespace hapticd;

void run(benchmark::State& st, const std::string& session, bool whole) {
  server::Session rig = bench::run_shipped_session("vishard10", session);
  server::DeviceSession& d = bench::first_device(rig);
  const server::SchemeChain& chain = d.chain().schemes[0];
  const ChainState cs = d.chain_state();
  const DeviceState state = d.state();
  const EngineInput engine;
  testing::PassThroughRenderPort render;
  TaskTarget task = d.task();
  JointTarget joints;
  joints.resize(10);
  JointCommand command;
  command.torque_nm = d.command().torque_nm;
  RedundancyResolution* redundancy = (*chain.inverse_kinematics)->redundancy();
  model::ModelData terms(*cs.model);
  std::uint64_t k = 2000;
  const auto one = [&] {
    const CycleTime t{static_cast<std::int64_t>(k) * 500'000, 500'000, k};
    ++k;
    if (whole) {
      model::compute_cycle_terms(*cs.model, terms, state.joints.position, state.joints.velocity, cs.handle_frame);
      benchmark::DoNotOptimize(terms.mass_matrix.data());
      (void)(*chain.virtual_model)->update(t, VirtualModelInput{state, cs, engine, render}, task);
    }
    (void)(*chain.inverse_kinematics)->update(t, InverseKinematicsInput{state, task, cs}, joints);
    if (whole) (void)chain.controller->update(t, ControllerInput{state, task, joints, cs, redundancy}, command);
    benchmark::DoNotOptimize(joints.position.data());
    benchmark::DoNotOptimize(command.torque_nm.data());
  };
  for (auto _ : st) one();
  constexpr int kRuns = 5000;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < kRuns; ++i) one();
  const double own = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / kRuns;
  const double reference = bench::seconds_per_model_terms(cs, state);
  st.counters["model_terms_us"] = reference * 1e6;
  st.counters["ratio_to_model_terms"] = own / reference;
}

const char* kSessions[] = {"admittance-pseudoinverse",
                           "admittance-weighted",
                           "admittance-damped",
                           "admittance-inertia-weighted",
                           "admittance-torque-level",
                           "admittance-computed-torque",
                           "admittance-partitioned",
                           "admittance-partitioned-wrist-pseudoinverse",
                           "admittance-partitioned-lookup-table"};

const bool kRegistered = [] {
  for (const char* s : kSessions) {
    benchmark::RegisterBenchmark((std::string("ik/") + s).c_str(), [s](benchmark::State& st) {
      run(st, s, false);
    })->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark((std::string("resolution/") + s).c_str(), [s](benchmark::State& st) {
      run(st, s, true);
    })->Unit(benchmark::kMicrosecond);
  }
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
