#include "scara_table.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "hapticd/input_file.hpp"

namespace hapticd::ik::vishard10 {
namespace {

constexpr double kPi = std::numbers::pi;

// The two-link chain from `from` to `to` (links a, b): the first link's world angle; false out of reach.
bool two_link(const Eigen::Vector2d& from, const Eigen::Vector2d& to, double a, double b, int branch, double& first,
              double& second) noexcept {
  const Eigen::Vector2d d = to - from;
  const double rho = d.norm();
  if (!(rho <= a + b + 1e-12) || !(rho >= std::abs(a - b) - 1e-12) || rho < 1e-12) return false;
  const double c = std::clamp((a * a + rho * rho - b * b) / (2.0 * a * rho), -1.0, 1.0);
  first = std::atan2(d.y(), d.x()) + (branch >= 0 ? 1.0 : -1.0) * std::acos(c);
  const Eigen::Vector2d knee = from + a * Eigen::Vector2d(std::cos(first), std::sin(first));
  const Eigen::Vector2d rest = to - knee;
  second = std::atan2(rest.y(), rest.x());
  return true;
}

double wrap(double a) noexcept { return std::remainder(a, 2.0 * kPi); }

}  // namespace

bool elbow_from_code(const Geometry& g, const Eigen::Vector2d& tip, double s, double t,
                     Eigen::Vector2d& elbow) noexcept {
  const double r1 = g.scara_link[0] + g.scara_link[1], r2 = g.scara_link[2] + g.scara_link[3];
  const double d = tip.norm();
  if (!(d > 1e-9) || d >= r1 + r2 || d <= std::abs(r1 - r2)) return false;
  const Eigen::Vector2d along = tip / d, across(-along.y(), along.x());
  const double a = (d * d + r1 * r1 - r2 * r2) / (2.0 * d);  // the chord, from the base
  const double h = std::sqrt(std::max(0.0, r1 * r1 - a * a));
  const double y = s * h;
  const double far = std::sqrt(std::max(0.0, r1 * r1 - y * y));       // circle 1's boundary along `along`
  const double near = d - std::sqrt(std::max(0.0, r2 * r2 - y * y));  // circle 2's
  const double x = 0.5 * (far + near) + t * 0.5 * (far - near);
  elbow = g.base + x * along + y * across;
  return true;
}

bool scara_joints_from_elbow(const Geometry& g, const Eigen::Vector2d& tip, const Eigen::Vector2d& elbow, int branch12,
                             int branch34, double q[4]) noexcept {
  double a1 = 0.0, a2 = 0.0, a3 = 0.0, a4 = 0.0;
  if (!two_link(g.base, elbow, g.scara_link[0], g.scara_link[1], branch12, a1, a2)) return false;
  if (!two_link(elbow, g.base + tip, g.scara_link[2], g.scara_link[3], branch34, a3, a4)) return false;
  q[0] = a1;
  q[1] = wrap(a2 - a1);
  q[2] = wrap(a3 - a2);
  q[3] = wrap(a4 - a3);
  return true;
}

Eigen::Vector2d ScaraTable::point(int i_radius, int i_angle) const noexcept {
  const double r =
      radius_count > 1 ? radius_min + (radius_max - radius_min) * i_radius / (radius_count - 1) : radius_min;
  const double a = angle_count > 1 ? angle_min + (angle_max - angle_min) * i_angle / (angle_count - 1) : angle_min;
  return r * Eigen::Vector2d(std::cos(a), std::sin(a));
}

bool ScaraTable::code_at(const Eigen::Vector2d& tip, Eigen::Vector2d& c, Eigen::Vector2d& clamped_tip) const noexcept {
  const double r_free = tip.norm(), a_free = std::atan2(tip.y(), tip.x());
  const double r = std::clamp(r_free, radius_min, radius_max), a = std::clamp(a_free, angle_min, angle_max);
  const double fr = (r - radius_min) / (radius_max - radius_min) * (radius_count - 1);
  const double fa = (a - angle_min) / (angle_max - angle_min) * (angle_count - 1);
  const int ir = std::min(static_cast<int>(fr), radius_count - 2), ia = std::min(static_cast<int>(fa), angle_count - 2);
  const double wr = fr - ir, wa = fa - ia;
  c = (1 - wr) * ((1 - wa) * at(ir, ia) + wa * at(ir, ia + 1)) +
      wr * ((1 - wa) * at(ir + 1, ia) + wa * at(ir + 1, ia + 1));
  clamped_tip = r * Eigen::Vector2d(std::cos(a), std::sin(a));
  return r == r_free && a == a_free;
}

bool ScaraTable::solve(const Geometry& g, const Eigen::Vector2d& tip, double q[4]) const noexcept {
  Eigen::Vector2d c, clamped;
  const bool inside = code_at(tip, c, clamped);
  Eigen::Vector2d elbow;
  if (!elbow_from_code(g, clamped, c.x(), c.y(), elbow)) return false;
  if (!scara_joints_from_elbow(g, clamped, elbow, branch12, branch34, q)) return false;
  return inside;
}

void ScaraTable::save(const std::filesystem::path& file, const std::string& header) const {
  std::ofstream out(file);
  if (!out) throw std::runtime_error("cannot write " + file.string());
  out.precision(17);
  std::istringstream lines(header);
  for (std::string l; std::getline(lines, l);) out << "# " << l << "\n";
  out << "radius " << radius_min << " " << radius_max << " " << radius_count << "\n";
  out << "angle " << angle_min << " " << angle_max << " " << angle_count << "\n";
  out << "branches " << branch12 << " " << branch34 << "\n";
  out << "worst_rate " << worst_rate << "\ntip_speed " << tip_speed << "\n";
  for (const auto& c : code) out << "code " << c.x() << " " << c.y() << "\n";
}

ScaraTable ScaraTable::load(const std::filesystem::path& file) {
  std::istringstream in(read_input_file(file, "SCARA table"));  // a regular file, size-limited
  ScaraTable t;
  int line_number = 0;
  const auto fail = [&](const std::string& what) {
    throw std::runtime_error(file.string() + ":" + std::to_string(line_number) + ": " + what);
  };
  for (std::string line; std::getline(in, line);) {
    ++line_number;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::string key;
    fields >> key;
    if (key == "radius") {
      fields >> t.radius_min >> t.radius_max >> t.radius_count;
    } else if (key == "angle") {
      fields >> t.angle_min >> t.angle_max >> t.angle_count;
    } else if (key == "branches") {
      fields >> t.branch12 >> t.branch34;
    } else if (key == "worst_rate") {
      fields >> t.worst_rate;
    } else if (key == "tip_speed") {
      fields >> t.tip_speed;
    } else if (key == "code") {
      Eigen::Vector2d c;
      fields >> c.x() >> c.y();
      if (fields && (std::abs(c.x()) > 1.0 || std::abs(c.y()) > 1.0)) fail("codes lie in [-1, 1]");
      t.code.push_back(c);
    } else {
      fail("unknown entry '" + key + "' (radius, angle, branches, worst_rate, tip_speed, code)");
    }
    if (!fields) fail("malformed '" + key + "' line");
  }
  if (t.radius_count < 2 || t.angle_count < 2 || !(t.radius_max > t.radius_min) || !(t.angle_max > t.angle_min))
    fail("the mesh needs at least 2 x 2 points over a positive radius and angle range");
  if (t.code.size() != static_cast<std::size_t>(t.radius_count * t.angle_count))
    fail("expected " + std::to_string(t.radius_count * t.angle_count) + " codes, got " + std::to_string(t.code.size()));
  return t;
}

}  // namespace hapticd::ik::vishard10
