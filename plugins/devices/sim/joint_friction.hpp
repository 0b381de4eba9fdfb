#pragma once
// Harmonic-drive joint friction at the joint output ([U06] device data (docs/references.md), "Joint friction data"):
// sliding friction as a 4th-order polynomial of |velocity| interpolated over the gear temperature (26, 32,
// 36 C curves; a warm-up drifts it from 26 C towards 36 C), load-dependent friction quadratic in the
// transmitted torque, and stiction with a break-away level that is drawn anew each time the joint sticks
// (poorly repeatable). Position-dependent ripple is a separate torque (see FlexibleChain). Each effect can
// be switched off. Real-time safe.
#include <array>
#include <random>

namespace hapticd::sim {

struct StribeckCurve {
  std::array<double, 5> p{};  // p0 .. p4: f = p4|v|^4 + p3|v|^3 + p2|v|^2 + p1|v| + p0  [N m vs rad/s]
};

struct FrictionParameters {
  bool sliding = true;
  bool load_dependent = true;
  bool stiction = true;
  bool warm_up = true;
  double scale = 1.0;  // per-joint variation of the whole friction
  // Gear size relative to the HFUC-17 the curves were measured on (rated torque ratio): scales the sliding
  // friction and the break-away, not the load-dependent part (which follows the transmitted torque).
  double size = 1.0;
  // The measured curves (spec), at 26, 32 and 36 C.
  std::array<double, 3> temperatures_c{26.0, 32.0, 36.0};
  std::array<StribeckCurve, 3> curves{StribeckCurve{{1.183, 1.008, -0.2642, 0.0487, -0.0037}},
                                      StribeckCurve{{1.050, 0.808, -0.2427, 0.0500, -0.0041}},
                                      StribeckCurve{{1.033, 0.619, -0.1509, 0.0257, -0.0019}}};
  double fit_velocity_max = 5.0;  // [rad/s] beyond it the curve continues with its slope there (>= 0)
  double start_temperature_c = 26.0;
  double end_temperature_c = 36.0;
  double warm_up_time_constant_s = 600.0;
  double load_a0 = 0.0, load_a1 = 0.02, load_a2 = 0.0;  // f_load = a2 t^2 + a1 |t| + a0
  double breakaway_min_nm = 1.19;                       // full break-away between these (spec), drawn per sticking
  double breakaway_max_nm = 1.5;
};

class JointFriction {
 public:
  void configure(const FrictionParameters& p, std::uint64_t seed);
  void reset() noexcept;

  // Sliding-friction magnitude at |v| (including the load term), at the current temperature.
  [[nodiscard]] double sliding_magnitude(double speed, double load_torque) const noexcept;
  // Advances the warm-up by dt.
  void advance_temperature(double dt) noexcept;
  [[nodiscard]] double temperature_c() const noexcept { return temperature_c_; }

  // One integration step of a coordinate with inertia `inertia` under the non-friction torque `drive`:
  // returns the new velocity, handling sticking, break-away and zero crossings. friction_out receives the
  // friction torque that acted (opposing motion).
  double step_velocity(double velocity, double drive, double load_torque, double inertia, double dt,
                       double& friction_out) noexcept;
  [[nodiscard]] bool stuck() const noexcept { return stuck_; }
  [[nodiscard]] double breakaway_nm() const noexcept { return breakaway_; }
  [[nodiscard]] const FrictionParameters& parameters() const noexcept { return p_; }

 private:
  [[nodiscard]] double curve(int i, double speed) const noexcept;
  void draw_breakaway() noexcept;

  FrictionParameters p_;
  double temperature_c_ = 26.0;
  double decay_dt_ = -1.0;
  double decay_ = 1.0;
  bool stuck_ = true;
  double breakaway_ = 1.3;
  std::mt19937_64 rng_;
};

}  // namespace hapticd::sim
