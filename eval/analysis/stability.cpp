#include "stability.hpp"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace hapticd::eval {
namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

Oscillation oscillation(std::span<const double> signal, double rate_hz, double cutoff_hz, double window_s) {
  if (!(rate_hz > 0.0) || !(cutoff_hz > 0.0) || cutoff_hz >= 0.5 * rate_hz) {
    throw std::invalid_argument("oscillation: the cutoff must lie between 0 and half the rate");
  }
  const auto window = static_cast<std::size_t>(std::llround(window_s * rate_hz));
  if (window == 0 || window > signal.size()) {
    throw std::invalid_argument("oscillation: the window (" + std::to_string(window) +
                                " samples) must be within the signal (" + std::to_string(signal.size()) + ")");
  }
  // Second-order Butterworth high-pass by the bilinear transform with prewarping.
  const double k = std::tan(kPi * cutoff_hz / rate_hz);
  const double q = 1.0 / std::sqrt(2.0);
  const double norm = 1.0 / (1.0 + k / q + k * k);
  const double b0 = norm, b1 = -2.0 * norm, b2 = norm;
  const double a1 = 2.0 * (k * k - 1.0) * norm, a2 = (1.0 - k / q + k * k) * norm;
  // From rest at the signal's first value (a constant offset is not an oscillation).
  double x1 = signal[0], x2 = signal[0], y1 = 0.0, y2 = 0.0, sum = 0.0;
  int crossings = 0;
  double first_crossing = -1.0, last_crossing = -1.0;
  for (std::size_t i = 0; i < signal.size(); ++i) {
    const double x = signal[i];
    const double y = b0 * x + b1 * x1 + b2 * x2 - a1 * y1 - a2 * y2;
    const double previous = y1;
    x2 = x1;
    x1 = x;
    y2 = y1;
    y1 = y;
    if (i + window < signal.size()) continue;
    sum += y * y;
    if (i + window > signal.size() && y != 0.0 && (y > 0.0) != (previous > 0.0)) {
      const double at = static_cast<double>(i) - y / (y - previous);  // interpolated between the samples
      if (first_crossing < 0.0) first_crossing = at;
      last_crossing = at;
      ++crossings;
    }
  }
  Oscillation o;
  o.rms = std::sqrt(sum / static_cast<double>(window));
  if (crossings >= 2) o.frequency_hz = 0.5 * (crossings - 1) * rate_hz / (last_crossing - first_crossing);
  return o;
}

namespace {

void check_range(double low, double high, double relative_tolerance) {
  if (!(low > 0.0) || !(high > low) || !(relative_tolerance > 0.0)) {
    throw std::invalid_argument("bisection: needs 0 < low < high and a positive tolerance");
  }
}

// Bisection in log(value) for a predicate that flips once between low and high; `good_low` says which side
// holds it. Returns the bracket as (last value on the low side, first on the high side).
Bisection bisect(const std::function<bool(double)>& holds, double low, double high, double relative_tolerance,
                 bool holds_above) {
  check_range(low, high, relative_tolerance);
  Bisection r;
  const bool at_low = holds(low);
  ++r.evaluations;
  const bool at_high = holds(high);
  ++r.evaluations;
  if (holds_above) {
    if (at_low) {
      r.below_range = true;
      r.value = low;
      return r;
    }
    if (!at_high) {
      r.above_range = true;
      r.value = high;
      r.unstable = high;
      return r;
    }
  } else {
    if (!at_low) {
      r.below_range = true;
      r.value = 0.0;
      r.unstable = low;
      return r;
    }
    if (at_high) {
      r.above_range = true;
      r.value = high;
      return r;
    }
  }
  double lo = low, hi = high;  // the predicate is at_low's at lo and at_high's at hi
  while (hi / lo > 1.0 + relative_tolerance) {
    const double mid = std::sqrt(lo * hi);
    const bool h = holds(mid);
    ++r.evaluations;
    if (h == at_low) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  r.value = holds_above ? hi : lo;
  r.unstable = holds_above ? lo : hi;
  return r;
}

}  // namespace

Bisection smallest_stable(const std::function<bool(double)>& stable, double low, double high,
                          double relative_tolerance) {
  return bisect(stable, low, high, relative_tolerance, true);
}

Bisection largest_stable(const std::function<bool(double)>& stable, double low, double high,
                         double relative_tolerance) {
  return bisect(stable, low, high, relative_tolerance, false);
}

double sampled_wall_energy_per_period(const SampledWall& device, double stiffness, double damping, double frequency_hz,
                                      int periods) {
  const double t = device.period_s;
  if (!(t > 0.0) || !(frequency_hz > 0.0) || frequency_hz * t >= 0.5 || periods < 1) {
    throw std::invalid_argument("sampled wall: needs T > 0, 0 < f < 1/(2T) and at least one period");
  }
  // Whole periods in a whole number of samples: the sequence is periodic, its sums are the steady state's.
  const auto n = static_cast<std::size_t>(std::llround(periods / (frequency_hz * t)));
  const double w = 2.0 * kPi * periods / (static_cast<double>(n) * t);
  const double amplitude = 1e-3;
  std::vector<double> x(n);
  for (std::size_t k = 0; k < n; ++k) x[k] = amplitude * std::sin(w * t * static_cast<double>(k));
  double energy = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double now = x[k], next = x[(k + 1) % n], before = x[(k + n - 1) % n];
    const double step = next - now;
    // Over [kT, (k+1)T]: constant velocity step/T through the damper b, and the held wall force.
    const double held = stiffness * now + damping * (now - before) / t;
    energy += device.damping_n_s_per_m * step * step / t + held * step;
  }
  return energy / periods;
}

bool sampled_wall_passive(const SampledWall& device, double stiffness, double damping) {
  // 200 frequencies up to 0.4975 / T, each with whole periods in 400 samples.
  constexpr int kSamples = 400;
  for (int j = 1; j < kSamples / 2; ++j) {
    const double f = j / (kSamples * device.period_s);
    if (sampled_wall_energy_per_period(device, stiffness, damping, f, j) < 0.0) return false;
  }
  return true;
}

}  // namespace hapticd::eval
