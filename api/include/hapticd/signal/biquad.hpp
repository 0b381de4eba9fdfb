#pragma once
// Second-order IIR sections (direct form II transposed) for joint-space and task-space signals, designed by
// the bilinear transform with pre-warping: Butterworth low-pass and notch (band-stop). One filter holds the
// coefficients and a state per channel; Vector is any fixed-capacity Eigen vector (JointVector, Vector3d, ...).
// Real-time safe: no allocation after reset(), no branches on the data.
#include <Eigen/Core>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <string>

namespace hapticd::signal {

struct BiquadCoefficients {
  double b0 = 1.0, b1 = 0.0, b2 = 0.0, a1 = 0.0, a2 = 0.0;  // a0 normalised to 1

  // Butterworth low-pass, cut-off fc (-3 dB) at sample rate fs. Not real-time safe (throws on bad input).
  static BiquadCoefficients lowpass(double fc, double fs) {
    check(fc, fs);
    const double k = std::tan(M_PI * fc / fs);
    const double q = 1.0 / std::sqrt(2.0);
    const double norm = 1.0 / (1.0 + k / q + k * k);
    BiquadCoefficients c;
    c.b0 = k * k * norm;
    c.b1 = 2.0 * c.b0;
    c.b2 = c.b0;
    c.a1 = 2.0 * (k * k - 1.0) * norm;
    c.a2 = (1.0 - k / q + k * k) * norm;
    return c;
  }
  // Notch at f0 with quality q (bandwidth f0 / q) at sample rate fs: zero gain at f0, unity far from it.
  static BiquadCoefficients notch(double f0, double q, double fs) {
    check(f0, fs);
    if (!(q > 0.0)) throw std::invalid_argument("notch quality must be positive");
    const double k = std::tan(M_PI * f0 / fs);
    const double norm = 1.0 / (1.0 + k / q + k * k);
    BiquadCoefficients c;
    c.b0 = (1.0 + k * k) * norm;
    c.b1 = 2.0 * (k * k - 1.0) * norm;
    c.b2 = c.b0;
    c.a1 = c.b1;
    c.a2 = (1.0 - k / q + k * k) * norm;
    return c;
  }
  // The analog section (s^2 + 2 zn w0 s + w0^2) / (s^2 + 2 zd w0 s + w0^2), w0 = 2 pi f0, by the bilinear
  // transform pre-warped at f0 (exact gain at f0): zn < zd gives a notch of depth zn / zd (the thesis's
  // torque notch uses zn = 0.01, zd = 0.2).
  static BiquadCoefficients analog_notch(double f0, double zeta_numerator, double zeta_denominator, double fs) {
    check(f0, fs);
    if (!(zeta_numerator >= 0.0) || !(zeta_denominator > 0.0)) {
      throw std::invalid_argument("notch damping ratios must be >= 0 (numerator) and > 0 (denominator)");
    }
    const double k = std::tan(M_PI * f0 / fs);  // s = (z - 1) / (z + 1) / k * w0 pre-warped: w0 / k scaling
    const double kk = k * k;
    const double n1 = 2.0 * zeta_numerator * k, d1 = 2.0 * zeta_denominator * k;
    const double norm = 1.0 / (1.0 + d1 + kk);
    BiquadCoefficients c;
    c.b0 = (1.0 + n1 + kk) * norm;
    c.b1 = 2.0 * (kk - 1.0) * norm;
    c.b2 = (1.0 - n1 + kk) * norm;
    c.a1 = c.b1;
    c.a2 = (1.0 - d1 + kk) * norm;
    return c;
  }
  // Magnitude of the frequency response at f (for tests and documentation).
  [[nodiscard]] double gain(double f, double fs) const noexcept {
    const double w = 2.0 * M_PI * f / fs;
    const std::complex<double> z1 = std::polar(1.0, -w), z2 = std::polar(1.0, -2.0 * w);
    return std::abs((b0 + b1 * z1 + b2 * z2) / (1.0 + a1 * z1 + a2 * z2));
  }

 private:
  static void check(double f, double fs) {
    if (!(fs > 0.0) || !(f > 0.0) || !(f < 0.5 * fs)) {
      throw std::invalid_argument("filter frequency " + std::to_string(f) + " Hz must lie in (0, " +
                                  std::to_string(0.5 * fs) + ") Hz at a sample rate of " + std::to_string(fs) + " Hz");
    }
  }
};

template <typename Vector>
class Biquad {
 public:
  Biquad() = default;
  explicit Biquad(const BiquadCoefficients& c) : c_(c) {}
  void set_coefficients(const BiquadCoefficients& c) noexcept { c_ = c; }

  // Starts in the steady state of a constant input x (no transient from zero).
  void reset(const Vector& x) noexcept {
    const double dc = (c_.b0 + c_.b1 + c_.b2) / (1.0 + c_.a1 + c_.a2);
    const Vector y = x * dc;
    // Direct form II transposed steady state: s1 = y - b0 x, s2 = b2 x - a2 y.
    s1_ = y - c_.b0 * x;
    s2_ = c_.b2 * x - c_.a2 * y;
  }
  Vector update(const Vector& x) noexcept {
    const Vector y = c_.b0 * x + s1_;
    s1_ = c_.b1 * x - c_.a1 * y + s2_;
    s2_ = c_.b2 * x - c_.a2 * y;
    return y;
  }

 private:
  BiquadCoefficients c_;
  Vector s1_, s2_;
};

}  // namespace hapticd::signal
