// Real-time factor of the simulated devices: one iteration is one 2 kHz control cycle (read + write) with
// every physical effect on (flexible joints, friction with warm-up, stiction, ripple, current loop, thermal
// model, encoders, force/torque sensor) and the simulated operator moving the handle; 20 kHz substeps.
// The counter real_time_factor is simulated time over wall time. Two integrators per device: the default
// multirate one (rigid-body terms at 4 kHz) and the single-rate one (rigid_body_hz: 0, every term every
// substep); the multirate benchmark also times both side by side (alternating blocks of cycles) and reports
// speedup_over_single_rate, a ratio independent of the machine's speed to first order.
#include <benchmark/benchmark.h>

#include <chrono>
#include <string>

#include "support/sim_device_fixture.hpp"

namespace {

const char* kOperator = "attachment: operator\noperator_motion: sine\noperator_motion_m: [0.03, 0.02, 0]\n";
const char* kSingleRate = "rigid_body_hz: 0\n";

void cycle(hapticd::test::SimRig& rig, int n) {
  rig.command.torque_nm = hapticd::JointVector::Constant(n, 0.2);
  rig.cycle();
  benchmark::DoNotOptimize(rig.state.joints.position.data());
}

// Seconds per cycle of each rig, timed in alternating blocks.
std::pair<double, double> side_by_side(hapticd::test::SimRig& a, hapticd::test::SimRig& b, int n) {
  constexpr int kBlocks = 6, kCycles = 1000;
  double ta = 0.0, tb = 0.0;
  for (int block = 0; block < kBlocks; ++block) {
    for (auto [rig, total] : {std::pair{&a, &ta}, std::pair{&b, &tb}}) {
      const auto start = std::chrono::steady_clock::now();
      for (int k = 0; k < kCycles; ++k) cycle(*rig, n);
      *total += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
  }
  return {ta / (kBlocks * kCycles), tb / (kBlocks * kCycles)};
}

void run(benchmark::State& state, const std::string& yaml, bool single_rate) {
  hapticd::test::SimRig rig(yaml + kOperator + (single_rate ? kSingleRate : ""));
  const int n = rig.device.description().dof();
  for (auto _ : state) cycle(rig, n);
  state.counters["real_time_factor"] =
      benchmark::Counter(static_cast<double>(rig.period_ns) * 1e-9, benchmark::Counter::kIsIterationInvariantRate);
  if (!single_rate) {
    hapticd::test::SimRig multi(yaml + kOperator), single(yaml + kOperator + kSingleRate);
    const auto [t_multi, t_single] = side_by_side(multi, single, n);
    state.counters["speedup_over_single_rate"] = t_single / t_multi;
  }
}

const std::pair<const char*, const char*> kDevices[] = {
    {"vishard3", "urdf: ../urdf/vishard3.urdf\ninitial_position: [-0.3, 1.6, 0.0]\npassive_gimbal: true\n"},
    {"vishard6", "urdf: ../urdf/vishard6.urdf\ninitial_position: [-0.5, 1.0, -0.5, 0.3, 0.3, 0.0]\n"},
    {"vishard10",
     "urdf: ../urdf/vishard10.urdf\ninitial_position: [0.3, -0.6, 0.6, -0.6, 0.3, 1.0, -2.0, 1.0, 0.8, 0.0]\n"},
};

const bool kRegistered = [] {
  for (const auto& [name, yaml] : kDevices) {
    const std::string y = yaml;
    benchmark::RegisterBenchmark((std::string("sim/") + name + "/control_cycle_2kHz").c_str(),
                                 [y](benchmark::State& s) { run(s, y, false); });
    benchmark::RegisterBenchmark((std::string("sim/") + name + "/control_cycle_2kHz_single_rate").c_str(),
                                 [y](benchmark::State& s) { run(s, y, true); });
  }
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
