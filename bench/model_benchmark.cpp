// The model toolbox against Orocos KDL in the same executable: per device, the per-cycle set a control chain
// needs (FK, J, dJ/dt qd, M, C qd, g of the handle) and forward dynamics. Prints the KDL/ours ratio of the
// medians at the end (run with --benchmark_repetitions for medians; scripts/bench.sh does).
#include <benchmark/benchmark.h>

#include <kdl/chainfdsolver_recursive_newton_euler.hpp>
#include <map>
#include <numbers>
#include <random>

#include "hapticd/model/dynamics.hpp"
#include "hapticd/model/kinematics.hpp"
#include "hapticd/model/urdf_loader.hpp"
#include "kdl_reference.hpp"

namespace {

using hapticd::JointVector;
namespace model = hapticd::model;

struct Fixture {
  explicit Fixture(const std::string& device)
      : robot(model::load_robot_model(std::string(HAPTICD_SOURCE_DIR) + "/config/urdf/" + device + ".urdf")),
        handle(robot.require_frame("handle")),
        data(robot),
        kdl(robot, handle) {
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(-std::numbers::pi, std::numbers::pi);
    for (int k = 0; k < kStates; ++k) {
      q[k].resize(robot.dof());
      qd[k].resize(robot.dof());
      for (int i = 0; i < robot.dof(); ++i) {
        q[k][i] = u(rng);
        qd[k][i] = u(rng);
      }
    }
  }
  static constexpr int kStates = 64;
  model::RobotModel robot;
  int handle;
  model::ModelData data;
  hapticd::reference::KdlSolvers kdl;
  std::array<JointVector, kStates> q, qd;
};

Fixture& fixture(const std::string& device) {
  static std::map<std::string, std::unique_ptr<Fixture>> fixtures;
  auto& f = fixtures[device];
  if (!f) f = std::make_unique<Fixture>(device);
  return *f;
}

void cycle_set_ours(benchmark::State& state, const std::string& device) {
  Fixture& f = fixture(device);
  int k = 0;
  for (auto _ : state) {
    model::compute_cycle_terms(f.robot, f.data, f.q[k], f.qd[k], f.handle);
    benchmark::DoNotOptimize(f.data.coriolis_torque.data());
    k = (k + 1) % Fixture::kStates;
  }
}

// The same with joint velocities in the subnormal range (below 2.2e-308), as a low-passed velocity estimate of a
// joint at rest passes through on its way to zero (no FTZ/DAZ on the loop thread): the cost of subnormal
// arithmetic in the cycle's model terms, against cycle_set/ours in the same run.
void cycle_set_subnormal_velocity(benchmark::State& state, const std::string& device) {
  Fixture& f = fixture(device);
  std::array<JointVector, Fixture::kStates> tiny;
  for (int k = 0; k < Fixture::kStates; ++k) tiny[k] = f.qd[k] * 1e-310;
  int k = 0;
  for (auto _ : state) {
    model::compute_cycle_terms(f.robot, f.data, f.q[k], tiny[k], f.handle);
    benchmark::DoNotOptimize(f.data.coriolis_torque.data());
    k = (k + 1) % Fixture::kStates;
  }
}

void cycle_set_kdl(benchmark::State& state, const std::string& device) {
  Fixture& f = fixture(device);
  auto& s = f.kdl;
  int k = 0;
  for (auto _ : state) {
    s.q.data = f.q[k];
    s.qd.data = f.qd[k];
    s.q_qd.q.data = f.q[k];
    s.q_qd.qdot.data = f.qd[k];
    s.fk.JntToCart(s.q, s.pose);
    s.jacobian.JntToJac(s.q, s.jac);
    s.jacobian_dot.JntToJacDot(s.q_qd, s.jac_dot_qd);
    s.dynamics.JntToMass(s.q, s.mass);
    s.dynamics.JntToCoriolis(s.q, s.qd, s.coriolis);
    s.dynamics.JntToGravity(s.q, s.gravity);
    benchmark::DoNotOptimize(s.gravity.data.data());
    k = (k + 1) % Fixture::kStates;
  }
}

void forward_dynamics_ours(benchmark::State& state, const std::string& device) {
  Fixture& f = fixture(device);
  JointVector tau = JointVector::Zero(f.robot.dof());
  JointVector qdd(f.robot.dof());
  int k = 0;
  for (auto _ : state) {
    model::forward_velocity(f.robot, f.data, f.q[k], f.qd[k]);
    model::forward_dynamics(f.robot, f.data, tau, qdd);
    benchmark::DoNotOptimize(qdd.data());
    k = (k + 1) % Fixture::kStates;
  }
}

void forward_dynamics_kdl(benchmark::State& state, const std::string& device) {
  Fixture& f = fixture(device);
  const KDL::Vector g(0, 0, -9.81);
  KDL::ChainFdSolver_RNE solver(f.kdl.chain, g);
  const unsigned n = f.kdl.chain.getNrOfJoints();
  KDL::JntArray q(n), qd(n), tau(n), qdd(n);
  const KDL::Wrenches wrenches(f.kdl.chain.getNrOfSegments(), KDL::Wrench::Zero());
  int k = 0;
  for (auto _ : state) {
    q.data = f.q[k];
    qd.data = f.qd[k];
    solver.CartToJnt(q, qd, tau, wrenches, qdd);
    benchmark::DoNotOptimize(qdd.data.data());
    k = (k + 1) % Fixture::kStates;
  }
}

// Collects the medians (or the single runs) to print the KDL / ours ratios after the console output.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& r : runs) {
      if (r.run_type == Run::RT_Aggregate && r.aggregate_name != "median") continue;
      times_[r.run_name.function_name] = r.GetAdjustedRealTime();
    }
  }
  void Finalize() override {
    ConsoleReporter::Finalize();
    print_ratios("KDL / hapticd", "/kdl", "kdl", "/ours", "ours");
    print_ratios("Subnormal joint velocities / normal ones", "/subnormal_velocity", "subnormal", "/ours", "normal");
  }

 private:
  // For every pair "<set><numerator>" and "<set><denominator>" of this run: both times and their ratio.
  void print_ratios(const char* title, const std::string& numerator, const char* numerator_label,
                    const std::string& denominator, const char* denominator_label) const {
    std::printf("\n%s time ratio (median real time, same run):\n", title);
    for (const auto& [name, below] : times_) {
      const auto pos = name.find(denominator);
      if (pos == std::string::npos) continue;
      const auto above = times_.find(name.substr(0, pos) + numerator);
      if (above == times_.end()) continue;
      std::printf("  %-32s %s %9.1f ns  %s %9.1f ns  ratio %5.2fx\n", name.substr(0, pos).c_str(), denominator_label,
                  below, numerator_label, above->second, above->second / below);
    }
  }
  std::map<std::string, double> times_;
};

}  // namespace

int main(int argc, char** argv) {
  for (const std::string device : {"vishard3", "vishard6", "vishard10"}) {
    benchmark::RegisterBenchmark((device + "/cycle_set/ours").c_str(), cycle_set_ours, device);
    benchmark::RegisterBenchmark((device + "/cycle_set/subnormal_velocity").c_str(), cycle_set_subnormal_velocity,
                                 device);
    benchmark::RegisterBenchmark((device + "/cycle_set/kdl").c_str(), cycle_set_kdl, device);
    benchmark::RegisterBenchmark((device + "/forward_dynamics/ours").c_str(), forward_dynamics_ours, device);
    benchmark::RegisterBenchmark((device + "/forward_dynamics/kdl").c_str(), forward_dynamics_kdl, device);
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  return 0;
}
