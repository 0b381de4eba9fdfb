#include "frequency_response.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hapticd::eval {
namespace {

constexpr double kPi = 3.14159265358979323846;

double wrap(double angle) {
  while (angle > kPi) angle -= 2.0 * kPi;
  while (angle <= -kPi) angle += 2.0 * kPi;
  return angle;
}

double decibel(double gain) { return 20.0 * std::log10(gain); }

}  // namespace

SineFit fit_sine(std::span<const double> time_s, std::span<const double> y, double frequency_hz) {
  if (time_s.size() != y.size()) throw std::invalid_argument("fit_sine: as many times as samples are needed");
  if (y.size() < 3) throw std::invalid_argument("fit_sine: at least 3 samples are needed");
  if (!(frequency_hz > 0.0)) throw std::invalid_argument("fit_sine: the frequency must be positive");
  // y = c + a sin(w t) + b cos(w t): linear in (c, a, b).
  const double w = 2.0 * kPi * frequency_hz;
  Eigen::MatrixXd basis(static_cast<Eigen::Index>(y.size()), 3);
  Eigen::VectorXd samples(static_cast<Eigen::Index>(y.size()));
  for (std::size_t k = 0; k < y.size(); ++k) {
    const auto r = static_cast<Eigen::Index>(k);
    basis(r, 0) = 1.0;
    basis(r, 1) = std::sin(w * time_s[k]);
    basis(r, 2) = std::cos(w * time_s[k]);
    samples(r) = y[k];
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(basis);
  if (qr.rank() < 3) throw std::invalid_argument("fit_sine: the samples do not determine a sinusoid");
  const Eigen::Vector3d p = qr.solve(samples);
  SineFit fit;
  fit.offset = p(0);
  fit.amplitude = std::hypot(p(1), p(2));
  fit.phase_rad = std::atan2(p(2), p(1));  // a sin + b cos = A sin(w t + phase)
  const Eigen::VectorXd fitted = basis * p;
  const double fit_rms = std::sqrt(fitted.squaredNorm() / static_cast<double>(y.size()));
  const double error_rms = std::sqrt((fitted - samples).squaredNorm() / static_cast<double>(y.size()));
  fit.distortion_percent = fit_rms > 0.0 ? 100.0 * error_rms / fit_rms : 0.0;
  return fit;
}

FrequencyPoint response_at(std::span<const double> time_s, std::span<const double> input,
                           std::span<const double> output, double frequency_hz) {
  const SineFit in = fit_sine(time_s, input, frequency_hz);
  const SineFit out = fit_sine(time_s, output, frequency_hz);
  if (!(in.amplitude > 0.0)) throw std::invalid_argument("response_at: the input has no component at the frequency");
  return FrequencyPoint{frequency_hz, out.amplitude / in.amplitude, wrap(out.phase_rad - in.phase_rad),
                        out.distortion_percent};
}

std::optional<double> bandwidth_3db(std::span<const FrequencyPoint> points) {
  if (points.empty() || !(points.front().gain > 0.0)) return std::nullopt;
  const double limit = decibel(points.front().gain) - 3.0103;  // 1/sqrt(2)
  for (std::size_t k = 1; k < points.size(); ++k) {
    const double now = points[k].gain > 0.0 ? decibel(points[k].gain) : -1e9;
    if (now > limit) continue;
    const double before = decibel(points[k - 1].gain);
    const double s = (before - limit) / (before - now);
    return points[k - 1].frequency_hz + s * (points[k].frequency_hz - points[k - 1].frequency_hz);
  }
  return std::nullopt;
}

std::optional<double> resonance_hz(std::span<const FrequencyPoint> points) {
  if (points.empty()) return std::nullopt;
  const auto peak = std::max_element(points.begin(), points.end(),
                                     [](const FrequencyPoint& a, const FrequencyPoint& b) { return a.gain < b.gain; });
  if (!(points.front().gain > 0.0) || decibel(peak->gain / points.front().gain) <= 1.0) return std::nullopt;
  return peak->frequency_hz;
}

}  // namespace hapticd::eval
