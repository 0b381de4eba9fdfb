// The safety supervisor with fault injection on the simulated devices (lockstep). Each test drives a device
// into one limit or watchdog and checks: what the limit does before a fault (damping, a wall, a clamp), the time
// to the safe state, the torque during the fade (no step), the fault report with its history, and that the
// other device of the session - a bystander - runs bit for bit as it does when nothing goes wrong.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "assembly/session_builder.hpp"
#include "hapticd/chain_state.hpp"
#include "hapticd/engine_input.hpp"
#include "hapticd/testing/allocation_guard.hpp"
#include "safety/safety_supervisor.hpp"
#include "safety/thermal_limiter.hpp"
#include "support/temp_file.hpp"
#include "support/test_paths.hpp"
#include "support/test_session.hpp"

namespace hapticd::server {
namespace {

using test::cycle_at;

// The simulated ViSHaRD3 in admittance control pushed by a scripted force, with a `safety` section. The fault
// tests below check the damping safe mode (zero torque after safe_damping_s): gravity_hold is off unless the
// section says otherwise (the gravity-holding safe mode has tests of its own).
std::string sim_device(const std::string& push, std::string safety, const std::string& model_extra = "") {
  if (safety.find("gravity_hold") == std::string::npos)
    safety = "gravity_hold: false" + (safety.empty() ? "" : ", " + safety);
  return test::sim_vishard3_device_yaml("v3", "constant", push) + R"(    virtual_model:
      plugin: admittance
      parameters: )" +
         test::flow_mapping("mass_kg: [3.0, 3.0, 3.0], damping_n_s_per_m: [40.0, 40.0, 40.0], rotation: false",
                            model_extra) +
         R"(
    controller:
      plugin: resolved_acceleration
      parameters: {task: translation}
    safety: )" +
         test::flow_mapping("", safety) + "\n";
}

struct Outcome {
  std::vector<JointVector> torque;        // device 0, every cycle
  std::vector<Eigen::Vector3d> position;  // device 0 handle
  std::vector<Eigen::Vector3d> velocity;  // device 0 handle
  std::vector<double> bystander;          // device 1 position
  DeviceFault fault = DeviceFault::none;
  std::uint64_t fault_cycle = 0;
  std::uint64_t at_rest_cycle = 0;  // first cycle at zero torque after the fault
  std::uint64_t limited_cycles = 0, render_limited_cycles = 0, recoveries = 0;
  DeviceFault final_fault = DeviceFault::none;
  bool has_report = false;
  std::unique_ptr<FaultReport> report = std::make_unique<FaultReport>();
};

// Runs `first_device` with a mass-spring bystander for `cycles`; `each(d, k)` runs before cycle k.
Outcome drive(const std::string& first_device, std::uint64_t cycles,
              const std::function<void(DeviceSession&, std::uint64_t)>& each = {}, std::uint32_t overruns_from = 0) {
  auto s = test::build_test_session("server: {clock: lockstep, seed: 7}\ndevices:\n" + first_device +
                                    test::mass_spring_device_yaml("b"));
  DeviceSession& d = *s.impl().devices[0];
  DeviceSession& b = *s.impl().devices[1];
  d.activate();
  b.activate();
  Outcome r;
  std::uint32_t consecutive = 0;
  for (std::uint64_t k = 0; k < cycles; ++k) {
    if (each) each(d, k);
    consecutive = overruns_from > 0 && k >= overruns_from ? consecutive + 1 : 0;
    d.cycle(cycle_at(k), 1.0, consecutive);
    b.cycle(cycle_at(k), 1.0);
    r.torque.push_back(d.command().torque_nm);
    r.position.push_back(d.chain_state().handle_pose.position);
    r.velocity.push_back(d.chain_state().handle_twist.linear);
    r.bystander.push_back(b.state().joints.position[0]);
    if (d.status().fault() != DeviceFault::none && r.fault == DeviceFault::none) {
      r.fault = d.status().fault();
      r.fault_cycle = d.status().fault_cycle();
    }
    if (r.fault != DeviceFault::none && r.at_rest_cycle == 0 && d.status().at_rest()) r.at_rest_cycle = k;
    if (!r.has_report) r.has_report = d.status().take_fault_report(*r.report);
    d.service();
  }
  EXPECT_EQ(b.status().fault(), DeviceFault::none);
  r.limited_cycles = d.status().limited_cycles();
  r.final_fault = d.status().fault();
  r.recoveries = d.status().recoveries();
  r.render_limited_cycles = d.status().render_limited_cycles();
  return r;
}

double largest_step(const Outcome& r, std::uint64_t from, std::uint64_t to) {
  double step = 0.0;
  for (std::uint64_t k = std::max<std::uint64_t>(from, 1); k < to && k < r.torque.size(); ++k)
    step = std::max(step, (r.torque[k] - r.torque[k - 1]).cwiseAbs().maxCoeff());
  return step;
}

// The common checks after a fault: safe state reached in safe_damping_s, no step larger than `max_step` N m per
// cycle from the fault on, the report carries the last 50 cycles up to the fault, the bystander undisturbed.
void expect_safe_stop(const Outcome& r, DeviceFault expected, const Outcome& reference, double max_step) {
  ASSERT_EQ(r.fault, expected) << fault_code(r.fault);
  ASSERT_GT(r.at_rest_cycle, 0u);
  const double to_rest_s = 0.0005 * static_cast<double>(r.at_rest_cycle - r.fault_cycle);
  EXPECT_LE(to_rest_s, 0.5 + 1e-9);
  // The fade and the damping onset: the first 100 ms of the safe mode (a device that fails on its own later -
  // a drive's speed monitor - goes to zero torque at once, which is its own safe state).
  const double step = largest_step(r, r.fault_cycle, r.fault_cycle + 200);
  std::printf("%s at %.3f s: zero torque %.3f s later; largest torque step after it %.3f N m\n",
              std::string(fault_code(expected)).c_str(), 0.0005 * static_cast<double>(r.fault_cycle), to_rest_s, step);
  EXPECT_LE(step, max_step);
  EXPECT_EQ(r.torque.back().cwiseAbs().maxCoeff(), 0.0);
  ASSERT_TRUE(r.has_report);
  EXPECT_EQ(r.report->fault, expected);
  EXPECT_EQ(r.report->cycle, r.fault_cycle);
  const auto expected_count = static_cast<std::uint32_t>(std::min<std::uint64_t>(50, r.fault_cycle));
  ASSERT_EQ(r.report->count, expected_count);
  EXPECT_EQ(r.report->records[expected_count - 1].cycle + 1, r.fault_cycle);
  EXPECT_EQ(r.report->records[0].cycle + expected_count, r.fault_cycle);
  EXPECT_EQ(r.bystander, reference.bystander) << "the other device was disturbed";
}

const std::string kNoPush = "[0.0, 0.0, 0.0]";

TEST(Safety, JointVelocityIsDampedFirstThenFaults) {
  // The bystander's reference: the same session with nothing going wrong.
  const Outcome reference = drive(sim_device(kNoPush, ""), 3000);
  // A 1-DOF device with a 0.2 m/s limit driven by a stiff PD towards a far target (sine setpoint amplitude
  // 0.05 m at 2 Hz = 0.63 m/s peak): damping from 0.15 m/s, fault at 0.19 m/s.
  const std::string fast =
      test::mass_spring_device_yaml("v3", ", velocity_limit_m_s: 0.2", "") + "    safety: {joint_damping_gain: 5.0}\n";
  const Outcome r = drive(fast, 3000);
  EXPECT_GT(r.limited_cycles, 0u);  // the damping acted before the fault
  expect_safe_stop(r, DeviceFault::joint_velocity, reference, 60.0 / 40.0 + 1.0);
  EXPECT_GT(std::abs(r.report->records[r.report->count - 1].velocity[0]), 0.15);  // the history shows the speed
}

TEST(Safety, HandleSpeedIsDampedFirstThenFaults) {
  const Outcome reference = drive(sim_device(kNoPush, ""), 4000);
  // 20 N on a light, undamped virtual mass: the handle speeds up through 0.3 m/s (damping) to 0.5 m/s (fault).
  const std::string safety = "speed_damping_from_m_s: 0.3, max_speed_m_s: 0.5";
  const Outcome damped = drive(sim_device("[6.0, 0.0, 0.0]", safety + ", speed_damping_n_s_per_m: 400",
                                          ", max_velocity_m_s: 3.0, damping_n_s_per_m: [20.0, 20.0, 20.0]"),
                               4000);
  EXPECT_EQ(damped.fault, DeviceFault::none) << "a moderate push is held by the damping";
  EXPECT_GT(damped.limited_cycles, 0u);
  double top = 0.0;
  for (const auto& v : damped.velocity) top = std::max(top, v.norm());
  std::printf("6 N: handle speed at most %.3f m/s (damping from 0.3, fault at 0.5)\n", top);
  EXPECT_LT(top, 0.5);
  const Outcome r = drive(
      sim_device("[40.0, 0.0, 0.0]", safety, ", max_velocity_m_s: 3.0, damping_n_s_per_m: [1.0, 1.0, 1.0]"), 4000);
  EXPECT_GT(r.limited_cycles, 0u);
  expect_safe_stop(r, DeviceFault::cartesian_velocity, reference, 10.0);
  EXPECT_GT(r.report->records[49].handle_velocity.norm(), 0.45);
}

TEST(Safety, WorkspaceWallsPushBackThenFault) {
  const Outcome reference = drive(sim_device(kNoPush, ""), 6000);
  // The box ends 20 mm in +x from the start (start x = device's own; found at cycle 0 of the reference).
  const double x0 = reference.position[0].x();
  const std::string box = "workspace_min_m: [-1.0, -1.0, -1.0], workspace_max_m: [" + std::to_string(x0 + 0.02) +
                          ", 1.0, 1.0], wall_stiffness_n_per_m: 3000";
  // 12 N: the wall holds the handle about 4 mm beyond it (12 / 3000 N/m), no fault.
  const Outcome held = drive(sim_device("[12.0, 0.0, 0.0]", box), 6000);
  EXPECT_EQ(held.fault, DeviceFault::none);
  const double beyond = held.position.back().x() - (x0 + 0.02);
  std::printf("12 N into the workspace wall: %.2f mm beyond it (12 N / 3000 N/m = 4 mm)\n", 1e3 * beyond);
  EXPECT_GT(beyond, 0.0);
  EXPECT_LT(beyond, 0.008);
  // With a soft wall (1000 N/m) 40 N go through by more than the 30 mm fault depth.
  const Outcome r =
      drive(sim_device("[40.0, 0.0, 0.0]", box + ", wall_stiffness_n_per_m: 1000, wall_fault_depth_m: 0.03"), 6000);
  expect_safe_stop(r, DeviceFault::workspace, reference, 10.0);
  EXPECT_GT(r.report->records[49].handle_position.x(), x0 + 0.045);
}

// An engine's input published every cycle (or by `input(k)`), as the DDS interface does.
std::function<void(DeviceSession&, std::uint64_t)> engine(
    std::function<EngineInput(const DeviceSession&, std::uint64_t)> input) {
  return [input](DeviceSession& d, std::uint64_t k) {
    if (k == 0) return;  // the chain state is known from cycle 0 on
    EngineInput e = input(d, k);
    e.sequence = k;
    d.requests().engine_input(e);
  };
}

TEST(Safety, RenderedForceAndItsRateAreLimited) {
  // The engine renders 200 N: limited to 30 N, rising at most 2000 N/s (1 N per cycle).
  const std::string coupling = ", coupling: true";
  const Outcome r =
      drive(sim_device(kNoPush, "max_force_n: 30, max_force_rate_n_per_s: 2000, soft_start_s: 0", coupling), 400,
            engine([](const DeviceSession&, std::uint64_t) {
              EngineInput e;
              e.has_wrench = true;
              e.wrench.force = Eigen::Vector3d(0.0, 200.0, 0.0);
              return e;
            }));
  EXPECT_EQ(r.fault, DeviceFault::none);
  EXPECT_GT(r.render_limited_cycles, 0u);
  // Replay through the snapshot values: the rendered force is the environment wrench of the task.
  auto s = test::build_test_session(
      "server: {clock: lockstep, seed: 7}\ndevices:\n" +
      sim_device(kNoPush, "max_force_n: 30, max_force_rate_n_per_s: 2000, soft_start_s: 0", coupling));
  DeviceSession& d = *s.impl().devices[0];
  d.activate();
  double largest = 0.0, largest_rate = 0.0, previous = 0.0;
  for (std::uint64_t k = 0; k < 400; ++k) {
    if (k > 0) {
      EngineInput e;
      e.has_wrench = true;
      e.wrench.force = Eigen::Vector3d(0.0, 200.0, 0.0);
      e.sequence = k;
      d.requests().engine_input(e);
    }
    d.cycle(cycle_at(k), 1.0);
    const double f = d.task().wrench.force.norm();
    largest = std::max(largest, f);
    largest_rate = std::max(largest_rate, std::abs(f - previous) * 2000.0);
    previous = f;
  }
  std::printf("200 N from the engine: rendered at most %.2f N, rising at most %.0f N/s\n", largest, largest_rate);
  EXPECT_NEAR(largest, 30.0, 1e-9);
  EXPECT_LE(largest_rate, 2000.0 + 1e-6);
}

// One cycle with a wrench engine's fresh input (sequence k + 1) asking for `force`.
void cycle_with_engine_wrench(DeviceSession& d, std::uint64_t k, const Eigen::Vector3d& force) {
  EngineInput e;
  e.has_wrench = true;
  e.wrench.force = force;
  e.sequence = k + 1;
  d.requests().engine_input(e);
  d.cycle(cycle_at(k), 1.0);
}

TEST(Safety, SoftStartRampsTheRenderedForceAtActivation) {
  // A wrench engine at 20 N from the first cycle on (engine ramp-in off): the rendered force follows the
  // soft-start ramp 0 -> limit over 0.2 s (max_force_n 40 N: 0.2 N per cycle) rather than stepping.
  const std::string device = sim_device(kNoPush, "max_force_n: 40, max_force_rate_n_per_s: 1.0e6", ", coupling: true") +
                             "    engine_ramp_in_s: 0.0\n";
  auto s = test::build_test_session("server: {clock: lockstep, seed: 7}\ndevices:\n" + device);
  DeviceSession& d = *s.impl().devices[0];
  d.activate();
  double previous = 0.0, largest_step = 0.0;
  std::uint64_t full = 0;
  for (std::uint64_t k = 0; k < 800; ++k) {
    cycle_with_engine_wrench(d, k, Eigen::Vector3d(0.0, 20.0, 0.0));
    const double f = d.task().wrench.force.norm();
    largest_step = std::max(largest_step, std::abs(f - previous));
    if (full == 0 && f >= 20.0 - 1e-9) full = k;
    previous = f;
  }
  std::printf("soft start: 20 N reached after %.1f ms, largest step %.3f N per cycle\n",
              0.5 * static_cast<double>(full), largest_step);
  EXPECT_NEAR(0.5 * static_cast<double>(full), 100.0, 1.0);  // 20 N of a 40 N limit rising over 200 ms
  EXPECT_LE(largest_step, 40.0 / 400.0 + 1e-9);
}

TEST(Safety, SoftStartRampsTheRenderedForceAgainAfterASchemeSwitch) {
  // The same 20 N engine wrench, rendered in full by the start scheme; at 0.5 s the device switches to an
  // alternative with the same kind of virtual model (stiffer damping): the rendered force drops to zero at the
  // switch and follows the soft-start ramp again (40 N over 0.2 s), no step; switching back ramps once more.
  const std::string device = sim_device(kNoPush, "max_force_n: 40, max_force_rate_n_per_s: 1.0e6", ", coupling: true") +
                             R"(    engine_ramp_in_s: 0.0
    schemes:
      - name: damped
        virtual_model:
          plugin: admittance
          parameters: {mass_kg: [3.0, 3.0, 3.0], damping_n_s_per_m: [80.0, 80.0, 80.0], rotation: false, coupling: true}
        controller: {plugin: resolved_acceleration, parameters: {task: translation}}
)";
  auto s = test::build_test_session("server: {clock: lockstep, seed: 7}\ndevices:\n" + device);
  DeviceSession& d = *s.impl().devices[0];
  d.activate();
  std::vector<double> force;
  for (std::uint64_t k = 0; k < 2400; ++k) {
    if (k == 1000) {
      EXPECT_TRUE(d.requests().switch_scheme("damped"));
    }
    if (k == 1800) {
      EXPECT_TRUE(d.requests().switch_scheme("default"));
    }
    cycle_with_engine_wrench(d, k, Eigen::Vector3d(0.0, 20.0, 0.0));
    force.push_back(d.task().wrench.force.norm());
    d.service();
  }
  EXPECT_EQ(d.schemes().active_name(), "default");
  EXPECT_EQ(d.schemes().switches(), 2u);
  EXPECT_EQ(d.status().fault(), DeviceFault::none);
  for (const std::uint64_t at : {std::uint64_t{1000}, std::uint64_t{1800}}) {
    EXPECT_NEAR(force[at - 1], 20.0, 1e-9);  // in full before the switch
    double largest_rise = 0.0;
    std::uint64_t full = 0;
    for (std::uint64_t k = at; k < at + 600; ++k) {
      largest_rise = std::max(largest_rise, force[k] - force[k - 1]);
      if (full == 0 && force[k] >= 20.0 - 1e-9) full = k - at;
    }
    std::printf(
        "switch at cycle %llu: rendered force %.2f N in the switching cycle, 20 N again after %.1f ms, largest "
        "rise per cycle %.3f N\n",
        static_cast<unsigned long long>(at), force[at], 0.5 * static_cast<double>(full), largest_rise);
    EXPECT_LE(force[at], 0.2 + 1e-9);                          // the ramp starts again from zero
    EXPECT_NEAR(0.5 * static_cast<double>(full), 100.0, 1.0);  // 20 N of a 40 N limit rising over 200 ms
    EXPECT_LE(largest_rise, 40.0 / 400.0 + 1e-9);
  }
}

TEST(Safety, ThermalModelDeratesToTheContinuousTorque) {
  // Unit level: a joint with peak 30, continuous 10 held at 30: the model's load 9 (1 - e^{-t/T}) reaches the
  // derating start 0.9 at t = T ln(9 / 8.1) = 0.105 T, and the limit settles where load = 1 at continuous.
  ThermalLimiter t;
  JointVector peak(1), cont(1), tau(1);
  peak << 30.0;
  cont << 10.0;
  t.configure(peak, cont, 10.0, 0.9, 0.001);
  double derate_at = -1.0;
  for (int k = 0; k < 60000; ++k) {
    tau[0] = std::min(30.0, t.limit()[0]);  // the command saturates at the limit
    t.update(tau);
    if (derate_at < 0.0 && t.derating()) derate_at = 0.001 * (k + 1);
  }
  std::printf("thermal: peak held %.3f s (model: %.3f s), limit after 60 s %.3f N m (continuous 10)\n", derate_at,
              10.0 * std::log(9.0 / 8.1), t.limit()[0]);
  EXPECT_NEAR(derate_at, 10.0 * std::log(9.0 / 8.1), 0.01);
  EXPECT_NEAR(t.limit()[0], 10.0, 0.2);
  EXPECT_LE(t.max_load(), 1.0 + 1e-3);
}

TEST(Safety, SafeModeWithAnUntrustedMeasurementStaysAtZeroTorque) {
  // Unit level: a safe mode that had to write zero (no valid velocity) never steps back up to the fade and the
  // damping when the measurement returns; with a valid velocity it fades the last torque out.
  DeviceDescription description;
  description.joints.push_back(JointDescription{"x", -1.0, 1.0, 10.0, 50.0, 20.0});
  SafetySupervisor supervisor;
  supervisor.configure(SafetySettings{}, description, 0.0005);
  JointVector last(1), velocity(1), torque(1);
  last << 10.0;
  velocity << 0.5;
  supervisor.enter_safe_mode(last);
  supervisor.safe_torque(last, velocity, false, nullptr, torque);
  EXPECT_EQ(torque[0], 0.0);
  EXPECT_TRUE(supervisor.at_rest());
  for (int k = 0; k < 100; ++k) {
    supervisor.safe_torque(last, velocity, true, nullptr, torque);
    ASSERT_EQ(torque[0], 0.0) << "cycle " << k;
  }
  supervisor.enter_safe_mode(last);
  supervisor.safe_torque(last, velocity, true, nullptr, torque);
  EXPECT_NEAR(torque[0], 10.0 * (1.0 - 1.0 / 40.0) - 3.0 * 0.5, 1e-12);  // fade 1/40 down, damping 3 N m s/rad
  EXPECT_FALSE(supervisor.at_rest());
}

TEST(Safety, ThermalLimitActsInTheChain) {
  // The 1-DOF device, peak 50 N, continuous 10 N, thermal time constant 2 s; the PD pushes to a far setpoint
  // (saturating): after 10 s the command is held near 10 N.
  const std::string hot =
      test::mass_spring_device_yaml("v3", ", continuous_force_n: 10.0, stiffness_n_per_m: 2000", ", kp: 100000") +
      "    safety: {thermal_time_constant_s: 2.0}\n";
  const Outcome r = drive(hot, 20000);
  EXPECT_EQ(r.fault, DeviceFault::none);
  double late = 0.0;
  for (std::size_t k = 18000; k < r.torque.size(); ++k) late = std::max(late, std::abs(r.torque[k][0]));
  double early = 0.0;
  for (std::size_t k = 0; k < 400; ++k) early = std::max(early, std::abs(r.torque[k][0]));
  std::printf(
      "thermal in the chain: largest force in the first 0.2 s %.1f N, in the last second %.2f N (continuous 10)\n",
      early, late);
  EXPECT_GT(early, 45.0);
  EXPECT_LT(late, 10.6);
}

TEST(Safety, ConsecutiveOverrunsStopTheDevice) {
  const Outcome reference = drive(sim_device(kNoPush, ""), 3000);
  const Outcome r = drive(sim_device(kNoPush, "max_consecutive_overruns: 5"), 3000, {}, 1000);
  expect_safe_stop(r, DeviceFault::loop_overrun, reference, 2.0);
  EXPECT_EQ(r.fault_cycle, 1004u);  // the fifth overrun in a row
}

TEST(Safety, DeviceWriteErrorsStopTheDevice) {
  const Outcome reference = drive(sim_device(kNoPush, ""), 2000);
  const Outcome r = drive(test::mass_spring_device_yaml("v3", ", fail_write_at_cycle: 500"), 2000);
  ASSERT_EQ(r.fault, DeviceFault::device_write);
  EXPECT_EQ(r.fault_cycle, 500u);
  EXPECT_EQ(r.bystander, reference.bystander);
}

TEST(Safety, SensorSaturationStopsTheDevice) {
  const Outcome reference = drive(sim_device(kNoPush, ""), 3000);
  // A sensor with a 30 N range, pushed with 40 N from 0.5 s on.
  const Outcome r =
      drive(test::sim_vishard3_device_yaml("v3", "step", "[40.0, 0.0, 0.0]") + R"(        wrench_force_start_s: 0.5
        sensor_force_range_n: [30.0, 30.0, 30.0]
    virtual_model:
      plugin: admittance
      parameters: {mass_kg: [3.0, 3.0, 3.0], damping_n_s_per_m: [400.0, 400.0, 400.0], rotation: false}
    controller:
      plugin: resolved_acceleration
      parameters: {task: translation}
    safety: {gravity_hold: false}
)",
            3000);
  expect_safe_stop(r, DeviceFault::sensor_saturation, reference, 10.0);
}

TEST(Safety, AnExceptionFromUpdateStopsOnlyItsDevice) {
  const Outcome reference = drive(sim_device(kNoPush, ""), 2000);
  const Outcome r = drive(test::mass_spring_device_yaml("v3", "", ", throw_at_cycle: 700"), 2000);
  expect_safe_stop(r, DeviceFault::plugin_exception, reference, 50.0 / 40.0 + 1.0);
  EXPECT_EQ(r.fault_cycle, 700u);
}

TEST(Safety, AnExceptionFromActivateStopsOnlyItsDevice) {
  // Against the contract, and not terminating the server: the chain never runs, the device is held safe.
  const Outcome r = drive(test::mass_spring_device_yaml("v3", "", ", throw_in_activate: true"), 500);
  EXPECT_EQ(r.fault, DeviceFault::activation);
  EXPECT_EQ(r.fault_cycle, 0u);
  EXPECT_EQ(r.final_fault, DeviceFault::activation);  // the bystander ran on unfaulted (drive checks it)
  EXPECT_GT(std::abs(r.bystander.back() - r.bystander.front()), 0.0);
}

TEST(Safety, NonFiniteOutputStopsOnlyItsDevice) {
  const Outcome reference = drive(sim_device(kNoPush, ""), 2000);
  const Outcome r = drive(test::mass_spring_device_yaml("v3", "", ", fault_at_cycle: 700"), 2000);
  expect_safe_stop(r, DeviceFault::non_finite_output, reference, 50.0 / 40.0 + 1.0);
}

TEST(Safety, EmergencyStopFadesDampsAndRecoversOnlyOnRequest) {
  const Outcome reference = drive(sim_device(kNoPush, ""), 6000);
  // E-stop at 1 s; a recovery asked at 1.1 s (it waits for zero torque), then the chain restarts softly.
  const Outcome r = drive(sim_device(kNoPush, ""), 6000, [&](DeviceSession& d, std::uint64_t k) {
    if (k == 1) {
      EXPECT_FALSE(d.requests().recover().accepted);  // nothing to recover from
    }
    if (k == 2000) d.requests().emergency_stop();
    if (k == 2200) {
      EXPECT_TRUE(d.requests().recover().accepted);
    }
    if (k == 2300) {
      EXPECT_EQ(d.status().fault(), DeviceFault::emergency_stop) << "recovered before the safe mode ended";
    }
  });
  ASSERT_EQ(r.fault, DeviceFault::emergency_stop);
  EXPECT_EQ(r.fault_cycle, 2000u);
  EXPECT_EQ(r.final_fault, DeviceFault::none) << fault_code(r.final_fault);
  EXPECT_EQ(r.recoveries, 1u);
  const double step = largest_step(r, 2000, 3000);
  std::printf("E-stop: zero torque %.3f s later, largest step %.3f N m; recovered\n",
              0.0005 * static_cast<double>(r.at_rest_cycle - 2000), step);
  EXPECT_LE(0.0005 * static_cast<double>(r.at_rest_cycle - 2000), 0.5 + 1e-9);
  EXPECT_LE(step, 2.0);
  ASSERT_TRUE(r.has_report);
  EXPECT_EQ(r.report->count, 50u);
  // After the recovery the chain runs again (it holds the handle against gravity: torque), without a fault.
  EXPECT_GT(r.torque.back().cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(r.bystander, reference.bystander);
}

TEST(Safety, PassivityControllerDissipatesWhatASampledStiffWallGenerates) {
  // An engine renders a stiff wall (8000 N/m) 5 mm in +x, but only every 20 ms (sample and hold): the held
  // force lags the motion, so the wall gives back more energy than it takes - an active environment. The
  // operator pushes 10 N into it. The observer sees the energy turn negative; with the controller on, the
  // port's energy never goes below zero by more than one step, and the dissipated energy is reported.
  const auto measure = [&](const std::string& passivity, double& lowest_energy, double& dissipated) {
    auto s = test::build_test_session("server: {clock: lockstep, seed: 7}\ndevices:\n" +
                                      sim_device("[10.0, 0.0, 0.0]",
                                                 passivity + "max_force_n: 300, max_force_rate_n_per_s: 1.0e6",
                                                 ", coupling: true, damping_n_s_per_m: [5.0, 5.0, 5.0]"));
    DeviceSession& d = *s.impl().devices[0];
    d.activate();
    Eigen::Vector3d held = Eigen::Vector3d::Zero();
    double wall_x = 0.0;
    lowest_energy = 0.0;
    for (std::uint64_t k = 0; k < 8000; ++k) {
      if (k == 1) wall_x = d.chain_state().handle_pose.position.x() + 0.005;
      if (k > 0) {
        if (k % 40 == 1) {
          const double depth = d.chain_state().handle_pose.position.x() - wall_x;
          held = Eigen::Vector3d(depth > 0.0 ? -8000.0 * depth : 0.0, 0.0, 0.0);
        }
        EngineInput e;
        e.has_wrench = true;
        e.wrench.force = held;
        e.sequence = k;
        d.requests().engine_input(e);
      }
      d.cycle(cycle_at(k), 1.0);
      lowest_energy = std::min(lowest_energy, d.safety().guard().port_energy_j());
      ASSERT_EQ(d.status().fault(), DeviceFault::none) << "cycle " << k;
    }
    dissipated = d.status().dissipated_j();
  };
  double low_off = 0.0, dis_off = 0.0, low_on = 0.0, dis_on = 0.0;
  measure("passivity_control: false, ", low_off, dis_off);
  measure("passivity_control: true, ", low_on, dis_on);
  std::printf(
      "sampled stiff wall: port energy at least %.4f J without the controller, %.4f J with it; dissipated %.4f J\n",
      low_off, low_on, dis_on);
  EXPECT_LT(low_off, -0.01) << "the sampled wall should be active (else this test proves nothing)";
  EXPECT_EQ(dis_off, 0.0);
  // Bounded damping (200 N s/m) cannot always take the whole excess at once: at most a few mJ remain.
  EXPECT_GT(low_on, -0.01);
  EXPECT_GT(low_on, 0.01 * low_off);
  EXPECT_GT(dis_on, 0.1);
}

TEST(Safety, APluginThatFailsToConfigureIsolatesItsDevice) {
  const std::string yaml = "server: {clock: lockstep, seed: 7}\ndevices:\n" +
                           test::mass_spring_device_yaml("broken", "", ", throw_in_configure: true") +
                           test::mass_spring_device_yaml("b");
  auto config = load_session_config(test::write_temp_file("isolate.yaml", yaml));
  config.server.plugin_paths.push_back(hapticd::test::plugin_dir());
  PluginLoader loader(config.server.plugin_paths);
  // Checking a session: an error naming the file, line and key.
  try {
    (void)build_sessions(config, loader);
    ADD_FAILURE() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("devices[0].controller"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("injected configure failure"), std::string::npos) << e.what();
  }
  // Running it: the broken device is held at zero torque, the other runs.
  std::vector<ConfigureFailure> failures;
  auto devices = build_sessions(config, loader, &failures);
  ASSERT_EQ(failures.size(), 1u);
  EXPECT_EQ(failures[0].device, "broken");
  ASSERT_EQ(devices.size(), 2u);
  EXPECT_EQ(devices[0]->status().fault(), DeviceFault::configure);
  EXPECT_FALSE(devices[0]->requests().recover().accepted);
  for (auto& d : devices) d->activate();
  for (std::uint64_t k = 0; k < 1000; ++k)
    for (auto& d : devices) d->cycle(cycle_at(k), 1.0);
  EXPECT_EQ(devices[0]->command().torque_nm[0], 0.0);
  EXPECT_EQ(devices[1]->status().fault(), DeviceFault::none);
  EXPECT_NE(devices[1]->command().torque_nm[0], 0.0);
  // Every device failing: the start fails.
  const std::string all_broken = "server: {clock: lockstep}\ndevices:\n" +
                                 test::mass_spring_device_yaml("broken", "", ", throw_in_configure: true");
  auto config2 = load_session_config(test::write_temp_file("all_broken.yaml", all_broken));
  config2.server.plugin_paths.push_back(hapticd::test::plugin_dir());
  std::vector<ConfigureFailure> failures2;
  EXPECT_THROW((void)build_sessions(config2, loader, &failures2), ConfigError);
}

TEST(Safety, TheSupervisedCycleDoesNotAllocate) {
  // Every limit engaged: walls, speed damping, thermal derating, render limits, passivity control, then a
  // fault and the safe mode.
  const double x0 = drive(sim_device(kNoPush, ""), 1).position[0].x();
  auto s = test::build_test_session(
      "server: {clock: lockstep, seed: 7}\ndevices:\n" +
      sim_device("[12.0, 0.0, 0.0]",
                 "workspace_min_m: [-1.0, -1.0, -1.0], workspace_max_m: [" + std::to_string(x0 + 0.005) +
                     ", 1.0, 1.0], speed_damping_from_m_s: 0.02, "
                     "thermal_time_constant_s: 0.5, passivity_control: true, max_force_n: 5",
                 ", coupling: true"));
  DeviceSession& d = *s.impl().devices[0];
  EngineInput e;
  e.has_wrench = true;
  e.wrench.force = Eigen::Vector3d(-20.0, 0.0, 0.0);
  d.requests().engine_input(e);
  EXPECT_EQ(test::allocations_over_cycles(d, 3000), 0u);
  d.requests().emergency_stop();
  std::size_t n = testing::count_allocations([&] {
    for (std::uint64_t k = 3001; k < 5000; ++k) d.cycle(cycle_at(k), 1.0);
  });
  EXPECT_EQ(n, 0u);
  EXPECT_EQ(d.status().fault(), DeviceFault::emergency_stop);  // not an earlier fault: the limits ran all along
  EXPECT_GT(d.status().limited_cycles(), 1000u);
  EXPECT_GT(d.status().render_limited_cycles(), 0u);
}

TEST(Safety, TheRenderPortRecordsWhatTheModelAskedOfIt) {
  // Plugin API 10: the port, not flags the model sets, tells the server that the wrench was limited and that the
  // model renders the supervisor's force - each cycle afresh.
  RenderGuard guard;
  RenderLimits limits;
  limits.max_force_n = 10.0;
  guard.configure(5e-4, limits, false, 0.0, 0.0);
  guard.begin_cycle(Eigen::Vector3d(1.0, 0.0, 0.0));
  EXPECT_FALSE(guard.limit_applied());
  EXPECT_FALSE(guard.safety_force_taken());
  RenderGuard::Vector6 w = RenderGuard::Vector6::Zero();
  w[0] = 50.0;
  (void)guard.limit(w);
  EXPECT_TRUE(guard.limit_applied());
  EXPECT_TRUE(guard.limited_this_cycle());  // it changed the wrench: the state flag render_limited
  EXPECT_EQ(guard.take_safety_force(), Eigen::Vector3d(1.0, 0.0, 0.0));
  EXPECT_TRUE(guard.safety_force_taken());
  guard.begin_cycle(Eigen::Vector3d::Zero());  // the next cycle: nothing asked yet
  EXPECT_FALSE(guard.limit_applied());
  EXPECT_FALSE(guard.limited_this_cycle());
  EXPECT_FALSE(guard.safety_force_taken());
  (void)guard.limit(RenderGuard::Vector6::Zero());  // within the limits: applied, nothing changed
  EXPECT_TRUE(guard.limit_applied());
  EXPECT_FALSE(guard.limited_this_cycle());
}

}  // namespace
}  // namespace hapticd::server
