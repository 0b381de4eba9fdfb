#include "mass_spring_device.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <ctime>
#include <numbers>
#include <stdexcept>
#include <string>

namespace hapticd::test_plugins {

ParameterSchema MassSpringDevice::parameter_schema() {
  ParameterSchema s;
  s.real("mass_kg", "moving mass").unit("kg").greater_than(0.0).default_value(1.0);
  s.real("stiffness_n_per_m", "spring to the rest position 0").unit("N/m").minimum(0.0).default_value(100.0);
  s.real("damping_n_s_per_m", "viscous damping").unit("N s/m").minimum(0.0).default_value(1.0);
  s.real("initial_position_m", "position at activation").unit("m").minimum(-1.0).maximum(1.0).default_value(0.0);
  s.real("force_limit_n", "actuator saturation (peak force)").unit("N").greater_than(0.0).default_value(50.0);
  s.integer("substeps", "integration steps per control period").minimum(1).maximum(1000).default_value(10);
  s.real("encoder_resolution_m", "position quantum; 0 is an ideal encoder").unit("m").minimum(0.0).default_value(0.0);
  s.real("position_noise_m", "standard deviation of Gaussian position noise (seeded)")
      .unit("m")
      .minimum(0.0)
      .default_value(0.0);
  s.integer("fail_read_at_cycle",
            "fault injection: read() fails from this cycle on (a latched drive fault: until reset_fault()); -1 never")
      .minimum(-1)
      .default_value(-1);
  s.boolean("refuse_fault_reset", "fault injection: reset_fault() fails").default_value(false);
  s.boolean("fail_enable", "fault injection: enable() fails").default_value(false);
  s.boolean("throw_in_disable", "fault injection: disable() throws").default_value(false);
  s.boolean("homing", "the device needs homing (capabilities.homing); read() fails until home()").default_value(false);
  s.boolean("fail_homing", "fault injection: home() fails").default_value(false);
  s.integer("fail_write_at_cycle", "fault injection: write() fails from this cycle on; -1 never")
      .minimum(-1)
      .default_value(-1);
  s.real("velocity_limit_m_s", "velocity limit in the description").unit("m/s").greater_than(0.0).default_value(10.0);
  s.real("continuous_force_n", "thermally sustainable force in the description; 0: the peak")
      .unit("N")
      .minimum(0.0)
      .default_value(0.0);
  s.real("tick_hz", "a clock of its own (server.clock: device): ticks at this rate from enable() on; 0: none")
      .unit("Hz")
      .minimum(0.0)
      .maximum(20000.0)
      .default_value(0.0);
  s.integer("ticks_before_pause", "fault injection: the clock stops ticking after this many ticks; -1 never")
      .minimum(-1)
      .default_value(-1);
  s.real("tick_pause_s", "... and starts again after this long; 0: never").unit("s").minimum(0.0).default_value(0.0);
  return s;
}

void MassSpringDevice::configure(const Parameters& p, const PluginContext& context) {
  mass_kg_ = p.real("mass_kg");
  stiffness_n_per_m_ = p.real("stiffness_n_per_m");
  damping_n_s_per_m_ = p.real("damping_n_s_per_m");
  initial_position_m_ = p.real("initial_position_m");
  force_limit_n_ = p.real("force_limit_n");
  substeps_ = p.integer("substeps");
  encoder_resolution_m_ = p.real("encoder_resolution_m");
  position_noise_m_ = p.real("position_noise_m");
  fail_read_at_cycle_ = p.integer("fail_read_at_cycle");
  fail_write_at_cycle_ = p.integer("fail_write_at_cycle");
  refuse_fault_reset_ = p.boolean("refuse_fault_reset");
  fail_enable_ = p.boolean("fail_enable");
  throw_in_disable_ = p.boolean("throw_in_disable");
  fail_homing_ = p.boolean("fail_homing");
  tick_hz_ = p.real("tick_hz");
  ticks_before_pause_ = p.integer("ticks_before_pause");
  tick_pause_s_ = p.real("tick_pause_s");
  period_s_ = 1.0 / context.rate_hz;
  // Semi-implicit Euler is stable for w dt < 2; keep a wide margin so the test device is also accurate.
  const double natural_hz = std::sqrt(stiffness_n_per_m_ / mass_kg_) / (2.0 * std::numbers::pi);
  const double substep_hz = context.rate_hz * static_cast<double>(substeps_);
  if (natural_hz > substep_hz / 20.0)
    throw ParameterError("stiffness_n_per_m", "natural frequency " + std::to_string(natural_hz) +
                                                  " Hz is too high for " + std::to_string(substeps_) +
                                                  " substeps at this rate (limit " + std::to_string(substep_hz / 20.0) +
                                                  " Hz): raise substeps or lower the stiffness");
  rng_.seed(context.seed);

  description_ = DeviceDescription{};
  description_.model = "test_mass_spring";
  const double continuous = p.real("continuous_force_n") > 0.0 ? p.real("continuous_force_n") : force_limit_n_;
  description_.joints.push_back(
      JointDescription{"x", -1.0, 1.0, p.real("velocity_limit_m_s"), force_limit_n_, continuous});
  description_.reports_joint_velocity = true;
  description_.simulated = true;
  description_.capabilities.homing = p.boolean("homing");
}

Outcome MassSpringDevice::enable() {
  if (fail_enable_) return Outcome::failure("injected enable failure (fail_enable)");
  read_fault_latched_ = false;
  homed_ = !description_.capabilities.homing;
  position_m_ = initial_position_m_;
  velocity_m_s_ = 0.0;
  force_n_ = 0.0;
  simulated_ns_ = 0;
  if (tick_hz_ > 0.0 && !ticking_.exchange(true)) {
    ticker_ = std::thread([this] {
      const auto period = static_cast<std::int64_t>(std::llround(1e9 / tick_hz_));
      std::int64_t next = realtime::TickSignal::now_ns(), ticked = 0;
      while (ticking_.load(std::memory_order_relaxed)) {
        if (ticks_before_pause_ >= 0 && ticked == ticks_before_pause_) {
          if (tick_pause_s_ <= 0.0) break;  // stopped for good
          next += static_cast<std::int64_t>(tick_pause_s_ * 1e9);
        }
        next += period;
        timespec ts{static_cast<time_t>(next / 1'000'000'000), static_cast<long>(next % 1'000'000'000)};
        while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
        }
        ticks_.tick(next);
        ++ticked;
      }
    });
  }
  return Outcome::success();
}

void MassSpringDevice::stop_ticking() noexcept {
  ticking_.store(false);
  if (ticker_.joinable()) ticker_.join();
}

void MassSpringDevice::step(double dt) noexcept {
  const double acceleration =
      (-stiffness_n_per_m_ * position_m_ - damping_n_s_per_m_ * velocity_m_s_ + force_n_) / mass_kg_;
  velocity_m_s_ += acceleration * dt;
  position_m_ += velocity_m_s_ * dt;
}

Outcome MassSpringDevice::read(const CycleTime& cycle, DeviceState& state) {
  if (!homed_) return Outcome::failure("not homed");
  if (fail_read_at_cycle_ >= 0 && cycle.index == static_cast<std::uint64_t>(fail_read_at_cycle_))
    read_fault_latched_ = true;
  if (read_fault_latched_) return Outcome::failure("injected read failure (fail_read_at_cycle)");
  // Advance to the cycle's time in fixed substeps; a gap of more than 10 periods (a stalled real-time loop)
  // is not integrated, which bounds the time read() takes.
  const std::int64_t substep_ns = std::max<std::int64_t>(1, cycle.period_ns / substeps_);
  const std::int64_t max_steps = 10 * substeps_;
  std::int64_t steps = 0;
  while (simulated_ns_ + substep_ns <= cycle.time_ns && steps < max_steps) {
    step(static_cast<double>(substep_ns) * 1e-9);
    simulated_ns_ += substep_ns;
    ++steps;
  }
  if (simulated_ns_ + substep_ns <= cycle.time_ns) simulated_ns_ = cycle.time_ns;

  double measured = position_m_;
  if (position_noise_m_ > 0.0) measured += position_noise_m_ * noise_(rng_);
  if (encoder_resolution_m_ > 0.0) measured = encoder_resolution_m_ * std::round(measured / encoder_resolution_m_);

  state.timestamp_ns = cycle.time_ns;
  state.joints.position[0] = measured;
  state.joints.velocity[0] = velocity_m_s_;
  state.joints.effort[0] = force_n_;
  return Outcome::success();
}

Outcome MassSpringDevice::write(const CycleTime& cycle, const JointCommand& command) {
  if (fail_write_at_cycle_ >= 0 && cycle.index >= static_cast<std::uint64_t>(fail_write_at_cycle_)) {
    force_n_ = 0.0;  // a failed write: the drive holds nothing
    return Outcome::failure("injected write failure (fail_write_at_cycle)");
  }
  const double f = command.torque_nm[0];
  if (!std::isfinite(f)) return Outcome::failure("non-finite force command");
  force_n_ = std::clamp(f, -force_limit_n_, force_limit_n_);
  return Outcome::success();
}

void MassSpringDevice::disable() {
  stop_ticking();
  force_n_ = 0.0;
  if (throw_in_disable_) throw std::runtime_error("injected disable failure (throw_in_disable)");
}

Outcome MassSpringDevice::home() {
  if (fail_homing_) return Outcome::failure("injected homing failure (fail_homing)");
  homed_ = true;
  return Outcome::success();
}

Outcome MassSpringDevice::reset_fault() {
  if (refuse_fault_reset_) return Outcome::failure("injected fault-reset failure (refuse_fault_reset)");
  read_fault_latched_ = false;
  return Outcome::success();
}

}  // namespace hapticd::test_plugins
