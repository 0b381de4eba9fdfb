#pragma once
// The stability analyses of the minimum-inertia and Z-width experiments (docs/evaluation.md, "Stability
// criterion"): an oscillation measure of a velocity signal, the bisection of a stability boundary, and the
// passivity of a sampled virtual wall on a one-joint device (Colgate and Brown's Z-width). Pure functions:
// tested on synthetic signals and an analytic model with known answers.
#include <functional>
#include <span>

namespace hapticd::eval {

// A signal's content above `cutoff_hz` (a second-order Butterworth high-pass, bilinear transform, run over the
// whole signal from its first value) over its last `window_s`: its RMS, and its frequency from the zero
// crossings (0 with fewer than two). The operator's own motion (below 1 Hz in the protocols) is removed; a limit
// cycle or a growing oscillation remains. Throws std::invalid_argument on a rate, cutoff or window that does not
// fit (cutoff at or above half the rate, window longer than the signal).
struct Oscillation {
  double rms = 0.0;
  double frequency_hz = 0.0;
};
[[nodiscard]] Oscillation oscillation(std::span<const double> signal, double rate_hz, double cutoff_hz,
                                      double window_s);

// The smallest value at which `stable` holds, for a predicate that is false below a boundary and true above
// it (a virtual inertia). Bisection in the logarithm of the value between `low` and `high` until the bracket's
// ratio is below 1 + relative_tolerance.
struct Bisection {
  double value = 0.0;        // the smallest stable value found (the bracket's upper end); `high` if none
  double unstable = 0.0;     // the largest unstable value found (the bracket's lower end); 0 if none
  bool below_range = false;  // stable already at `low`: value = low, the boundary lies at or below it
  bool above_range = false;  // unstable even at `high`: no stable value in the range
  int evaluations = 0;
};
// Throws std::invalid_argument unless 0 < low < high and relative_tolerance > 0.
[[nodiscard]] Bisection smallest_stable(const std::function<bool(double)>& stable, double low, double high,
                                        double relative_tolerance);
// The same for a predicate that holds below a boundary and fails above it (a wall's stiffness): the largest
// value at which it holds. below_range: fails already at `low`; above_range: holds at `high`.
[[nodiscard]] Bisection largest_stable(const std::function<bool(double)>& stable, double low, double high,
                                       double relative_tolerance);

// A one-joint haptic device (physical damping b; its mass stores energy but dissipates none) rendering a virtual
// wall (stiffness K, damping B) that is sampled every T, its velocity a backward difference, its force held over
// the period (Colgate and Brown, 1994). The net energy the device port absorbs while the operator moves it
// through a sinusoid at `frequency_hz` (amplitude 1 mm, `periods` whole periods from the wall's surface, the wall
// bilateral), at constant velocity between the samples - of all motions through the same samples the one that
// dissipates least in b, the worst case of the passivity proof -, per period: negative where the device gives
// out more energy than it takes (not passive). Exact sums, no integration error.
struct SampledWall {
  double damping_n_s_per_m = 1.0;  // b
  double period_s = 0.001;         // T
};
[[nodiscard]] double sampled_wall_energy_per_period(const SampledWall& device, double stiffness, double damping,
                                                    double frequency_hz, int periods = 20);
// Passive: the port absorbs energy at every frequency of a sweep over (0, the Nyquist frequency).
[[nodiscard]] bool sampled_wall_passive(const SampledWall& device, double stiffness, double damping);

}  // namespace hapticd::eval
