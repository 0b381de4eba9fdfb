#pragma once
#include <atomic>
#include <cstdint>
#include <random>
#include <thread>

#include "hapticd/device.hpp"
#include "hapticd/realtime/tick_signal.hpp"

namespace hapticd::test_plugins {

// A 1-DOF mass on a spring with viscous damping: m xdd = -k x - c xd + u, u the commanded force saturated at
// force_limit_n. Integrated (semi-implicit Euler) in substeps up to each cycle's time; optional encoder
// quantisation and seeded Gaussian position noise; optional injected read failure for fault tests. With tick_hz it
// has a clock of its own (as an SDK that owns the servo loop): a thread ticks at that rate from enable() to
// disable(), and can stop ticking after a number of ticks (a device that stops calling back) and start again.
class MassSpringDevice final : public Device {
 public:
  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const PluginContext& context) override;
  [[nodiscard]] const DeviceDescription& description() const override { return description_; }
  Outcome enable() override;
  Outcome read(const CycleTime& cycle, DeviceState& state) override;
  Outcome write(const CycleTime& cycle, const JointCommand& command) override;
  void disable() override;
  Outcome home() override;
  Outcome reset_fault() override;
  DeviceClock* clock() noexcept override { return tick_hz_ > 0.0 ? &ticks_ : nullptr; }
  ~MassSpringDevice() override { stop_ticking(); }

 private:
  void stop_ticking() noexcept;
  void step(double dt) noexcept;

  DeviceDescription description_;
  double mass_kg_ = 1.0;
  double stiffness_n_per_m_ = 0.0;
  double damping_n_s_per_m_ = 0.0;
  double initial_position_m_ = 0.0;
  double force_limit_n_ = 0.0;
  double encoder_resolution_m_ = 0.0;
  double position_noise_m_ = 0.0;
  std::int64_t substeps_ = 1;
  std::int64_t fail_read_at_cycle_ = -1;
  std::int64_t fail_write_at_cycle_ = -1;
  bool refuse_fault_reset_ = false, fail_enable_ = false, fail_homing_ = false, throw_in_disable_ = false;
  bool read_fault_latched_ = false, homed_ = true;
  double period_s_ = 0.0005;
  double tick_hz_ = 0.0;
  std::int64_t ticks_before_pause_ = -1;
  double tick_pause_s_ = 0.0;
  realtime::TickSignal ticks_;
  std::thread ticker_;
  std::atomic<bool> ticking_{false};

  double position_m_ = 0.0;
  double velocity_m_s_ = 0.0;
  double force_n_ = 0.0;
  std::int64_t simulated_ns_ = 0;
  std::mt19937_64 rng_;
  std::normal_distribution<double> noise_{0.0, 1.0};
};

}  // namespace hapticd::test_plugins
