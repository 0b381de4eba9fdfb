#pragma once
// The joint friction model of the compensators ([U06] methods 1, "Friction model used for
// compensation"), and its least-squares identification:
//   sliding magnitude  f(|qd|, t) = p0 + p1|qd| + p2|qd|^2 + p3|qd|^3 + p4|qd|^4 + a2 t^2 + a1|t| + a0,
// with t the load torque transmitted by the joint. Beyond velocity_max (the highest velocity seen in the
// identification) the polynomial is held constant: polynomials extrapolate badly. Evaluation is real-time
// safe; fitting allocates (worker threads and tools only).
#include <array>
#include <optional>
#include <span>
#include <string>

#include "hapticd/export.hpp"

namespace hapticd::model {

struct HAPTICD_API FrictionModel {
  std::array<double, 5> p{};     // p0 (Coulomb) .. p4 [N m, N m s/rad, ...]
  std::array<double, 3> load{};  // a0, a1, a2
  double velocity_max = 5.0;     // [rad/s]
  double breakaway_nm = 0.0;     // measured break-away torque at rest (information; 0: unknown)

  // Sliding-friction magnitude (>= 0) at |velocity| and load torque.
  [[nodiscard]] double magnitude(double velocity, double load_torque) const noexcept;
  // The velocity-dependent part only (load-free).
  [[nodiscard]] double sliding(double velocity) const noexcept;
};

// One averaged friction sample for a fit.
struct FrictionSample {
  double speed;   // |qd| [rad/s], > 0
  double torque;  // friction magnitude [N m]
  double weight = 1.0;
};

// Least-squares fit of p0..p4 (load part unchanged, velocity_max = the highest sample speed). Returns nothing
// when the samples do not excite the fit (fewer than 6 distinct speeds or a rank-deficient system).
// regularization > 0 pulls the coefficients towards base's (ridge, relative to the summed weights): on-line
// re-tuning over a narrow speed range then stays near the previous curve where the data says little.
[[nodiscard]] HAPTICD_API std::optional<FrictionModel> fit_sliding_friction(std::span<const FrictionSample> samples,
                                                                            const FrictionModel& base,
                                                                            double regularization = 0.0);

// Least-squares fit of a0..a2: each sample holds the |load torque| in `speed` and the friction above the
// load-free curve in `torque`.
[[nodiscard]] HAPTICD_API std::optional<std::array<double, 3>> fit_load_friction(
    std::span<const FrictionSample> samples);

}  // namespace hapticd::model
