// Real-time factor of the simulated devices: one iteration is one 2 kHz control cycle (read + write) with
// every physical effect on (flexible joints, friction with warm-up, stiction, ripple, current loop, thermal
// model, encoders, force/torque sensor) and the simulated operator moving the handle; 20 kHz substeps.
// The counter real_time_factor is simulated time over wall time.
#include <benchmark/benchmark.h>

#include "support/sim_device_fixture.hpp"

namespace {

const char* kOperator = "attachment: operator\noperator_motion: sine\noperator_motion_m: [0.03, 0.02, 0]\n";

void run(benchmark::State& state, const std::string& yaml) {
  hapticd::test::SimRig rig(yaml + kOperator);
  const int n = rig.device.description().dof();
  for (auto _ : state) {
    rig.command.torque_nm = hapticd::JointVector::Constant(n, 0.2);
    rig.cycle();
    benchmark::DoNotOptimize(rig.state.joints.position.data());
  }
  state.counters["real_time_factor"] =
      benchmark::Counter(static_cast<double>(rig.period_ns) * 1e-9, benchmark::Counter::kIsIterationInvariantRate);
}

void vishard3(benchmark::State& s) {
  run(s, "urdf: ../urdf/vishard3.urdf\ninitial_position: [-0.3, 1.6, 0.0]\npassive_gimbal: true\n");
}
void vishard6(benchmark::State& s) {
  run(s, "urdf: ../urdf/vishard6.urdf\ninitial_position: [-0.5, 1.0, -0.5, 0.3, 0.3, 0.0]\n");
}
void vishard10(benchmark::State& s) {
  run(s,
      "urdf: ../urdf/vishard10.urdf\n"
      "initial_position: [0.3, -0.6, 0.6, -0.6, 0.3, 1.0, -2.0, 1.0, 0.8, 0.0]\n");
}

}  // namespace

BENCHMARK(vishard3)->Name("sim/vishard3/control_cycle_2kHz");
BENCHMARK(vishard6)->Name("sim/vishard6/control_cycle_2kHz");
BENCHMARK(vishard10)->Name("sim/vishard10/control_cycle_2kHz");
BENCHMARK_MAIN();
