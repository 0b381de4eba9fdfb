#include "profile.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hapticd {

Profile::Kind Profile::parse(const std::string& name) {
  if (name == "constant") return Kind::constant;
  if (name == "step") return Kind::step;
  if (name == "ramp") return Kind::ramp;
  if (name == "sine") return Kind::sine;
  if (name == "shuttle") return Kind::shuttle;
  throw std::invalid_argument("profile '" + name + "': use constant, step, ramp, sine or shuttle");
}

Eigen::Vector3d Profile::shuttle(double t) const noexcept {
  const double distance = value.norm();
  if (t < start_s || distance <= 0.0 || acceleration <= 0.0 || speed <= 0.0) return Eigen::Vector3d::Zero();
  // In units of the distance: one leg accelerates at a to v (or to its peak, if it is too short), cruises and
  // decelerates at a.
  const double a = acceleration / distance;
  const double v = std::min(speed / distance, std::sqrt(a));  // triangular when the leg is too short
  const double ta = v / a;
  const double tc = (1.0 - v * ta) / v;
  const double leg = 2.0 * ta + tc;
  const double local = std::fmod(t - start_s, 2.0 * leg);
  const bool back = local >= leg;
  const double tau = back ? local - leg : local;
  Eigen::Vector3d s;  // progress, rate, acceleration along the leg
  if (tau < ta) {
    s << 0.5 * a * tau * tau, a * tau, a;
  } else if (tau < ta + tc) {
    s << 0.5 * a * ta * ta + v * (tau - ta), v, 0.0;
  } else {
    const double r = leg - tau;
    s << 1.0 - 0.5 * a * r * r, a * r, -a;
  }
  if (back) s = Eigen::Vector3d(1.0 - s[0], -s[1], -s[2]);
  return s;
}

}  // namespace hapticd
