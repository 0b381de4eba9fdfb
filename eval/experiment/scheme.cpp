#include "scheme.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace hapticd::eval {

Scheme open_loop_impedance() {
  return {"open-loop", "open-loop impedance", Scheme::Display::impedance, "impedance", "force_gain: 0", 0.0,
          0.0,         "open-loop",           "open-loop impedance"};
}

Scheme pd_force_feedback(double kp, double kd) {
  return {fmt::format("pd-kp{:g}-kd{:g}", kp, kd),
          fmt::format("PD force feedback, Kp {:g}, Kd {:g}", kp, kd),
          Scheme::Display::impedance,
          "impedance",
          fmt::format("force_gain: {:.17g}, force_derivative_gain: {:.17g}", kp, kd),
          0.0,
          kp,
          fmt::format("pd-kp{:g}-kd{:g}", kp, kd),
          fmt::format("PD force feedback, Kp {:g}, Kd {:g}", kp, kd)};
}

Scheme admittance(const std::string& inner, double kp, double virtual_mass_kg, bool feedforward) {
  std::string plugin;
  if (inner == "rac") {
    plugin = "resolved_acceleration";
  } else if (inner == "ijc") {
    plugin = "inverse_jacobian";
  } else if (inner == "tjc") {
    plugin = "transposed_jacobian";
  } else if (inner == "ctc") {
    plugin = "computed_torque";
  } else {
    throw std::invalid_argument("unknown inner loop '" + inner + "' (rac, ijc, tjc, ctc)");
  }
  std::string upper;
  for (char c : inner) upper += static_cast<char>(c - 'a' + 'A');
  Scheme s{fmt::format("{}-kp{:g}-m{:g}{}", inner, kp, virtual_mass_kg, feedforward ? "-ff" : ""),
           fmt::format("{}, kp {:g}, {:g} kg{}", upper, kp, virtual_mass_kg, feedforward ? ", feedforward" : ""),
           Scheme::Display::admittance,
           plugin,
           fmt::format("bandwidth_rad_s: {:.17g}, damping_ratio: 1, acceleration_feedforward: {}", std::sqrt(kp),
                       feedforward),
           virtual_mass_kg,
           0.0,
           fmt::format("{}-kp{:g}{}", inner, kp, feedforward ? "-ff" : ""),
           fmt::format("{}, kp {:g}{}", upper, kp, feedforward ? ", feedforward" : "")};
  s.joint_space = inner == "ctc";
  return s;
}

}  // namespace hapticd::eval

namespace hapticd::eval {
namespace {

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::size_t begin = 0;
  while (true) {
    const std::size_t end = text.find(separator, begin);
    parts.push_back(text.substr(begin, end - begin));
    if (end == std::string::npos) return parts;
    begin = end + 1;
  }
}

double number(const std::string& text, const std::string& whole) {
  try {
    std::size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size() && std::isfinite(v) && v >= 0.0) return v;
  } catch (const std::exception&) {
  }
  throw std::invalid_argument("scheme '" + whole + "': '" + text + "' is not a non-negative number");
}

}  // namespace

Scheme parse_scheme(const std::string& text, double virtual_mass_kg) {
  const std::vector<std::string> p = split(text, ':');
  if (p[0] == "open-loop" && p.size() == 1) return open_loop_impedance();
  if (p[0] == "pd" && p.size() == 3) return pd_force_feedback(number(p[1], text), number(p[2], text));
  if ((p[0] == "rac" || p[0] == "ijc" || p[0] == "tjc" || p[0] == "ctc") && (p.size() == 2 || p.size() == 3)) {
    if (p.size() == 3 && p[2] != "ff")
      throw std::invalid_argument("scheme '" + text + "': the third part is 'ff' or nothing");
    const double kp = number(p[1], text);
    if (kp <= 0.0) throw std::invalid_argument("scheme '" + text + "': kp must be positive");
    return admittance(p[0], kp, virtual_mass_kg, p.size() == 3);
  }
  throw std::invalid_argument("unknown scheme '" + text +
                              "' (open-loop, pd:KP:KD, rac:KP[:ff], ijc:KP[:ff], tjc:KP[:ff], ctc:KP[:ff])");
}

}  // namespace hapticd::eval
