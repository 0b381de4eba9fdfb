#pragma once
// The analysis of the dynamic force precision experiment (../shared/spec/CONTROL-METHODS.md section 4, "Dynamic
// force precision"; docs/evaluation.md): per excitation frequency, the least-squares sinusoid at that frequency
// fitted to the commanded and to the measured force -> gain and phase; the distortion
// D_rms = 100 % * rms(fit - measured) / rms(fit); over the frequencies, the -3 dB bandwidth and the resonance.
// Pure functions of the samples: tested on synthetic signals with known answers.
#include <optional>
#include <span>

namespace hapticd::eval {

// y(t) ~ offset + amplitude * sin(2 pi f t + phase_rad), least squares over the samples.
struct SineFit {
  double amplitude = 0.0;
  double phase_rad = 0.0;
  double offset = 0.0;
  double distortion_percent = 0.0;  // 100 * rms(fit - y) / rms(fit)
};
// Throws std::invalid_argument when the sizes differ, there are fewer than 3 samples, the frequency is not
// positive, or the samples do not determine a sinusoid (all at one phase).
[[nodiscard]] SineFit fit_sine(std::span<const double> time_s, std::span<const double> y, double frequency_hz);

// The response of `output` to `input` at the excitation frequency: both fitted there.
struct FrequencyPoint {
  double frequency_hz = 0.0;
  double gain = 0.0;                // output amplitude / input amplitude
  double phase_rad = 0.0;           // output phase - input phase, in (-pi, pi]
  double distortion_percent = 0.0;  // the output's
};
[[nodiscard]] FrequencyPoint response_at(std::span<const double> time_s, std::span<const double> input,
                                         std::span<const double> output, double frequency_hz);

// The -3 dB bandwidth: the first frequency (in the points' order, ascending) where the gain falls to 1/sqrt(2) of
// the first point's, interpolated linearly in dB between the two points around it; none if it never does.
[[nodiscard]] std::optional<double> bandwidth_3db(std::span<const FrequencyPoint> points);
// The resonance: the frequency of the largest gain, when it exceeds the first point's by more than 1 dB.
[[nodiscard]] std::optional<double> resonance_hz(std::span<const FrequencyPoint> points);

}  // namespace hapticd::eval
