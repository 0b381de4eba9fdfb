#include "minimum_inertia_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <optional>

#include "analysis/stability.hpp"
#include "device_presets.hpp"
#include "eval_options.hpp"
#include "experiment/device_model.hpp"
#include "experiment/rig.hpp"
#include "experiment/stability_trial.hpp"
#include "report/progress.hpp"

namespace hapticd::eval {
namespace {

struct Options {
  CommonOptions common;
  std::vector<std::string> schemes;     // empty: the device's (default_schemes)
  std::vector<std::string> directions;  // empty: x y z, and rx ry rz on devices that render rotations
  std::vector<std::string> loads{"firm-grasp", "loose-grasp", "voluntary-motion", "wall-collision"};
  double low_kg = 0.2, high_kg = 20.0, tolerance = 0.05;
  double low_kg_m2 = 0.001, high_kg_m2 = 5.0;
  double other_axes_kg = 10.0;    // the mass of the directions not under test (per-direction)
  double other_axes_kg_m2 = 1.0;  // the rotational inertia of the directions not under test (per-direction)
  // The translational mass's shape. per-direction: the mass under test on its own axis, the others heavy
  // (other_axes_kg); isotropic: the same mass on every axis (a pure mass m I), pushed along each direction in
  // turn. Empty: the device's (default_shape). Rotations are always per direction (the thesis's diagonals).
  std::string shape;
};

// How the thesis reports the device's minimum mass: one figure - a pure mass m I - on ViSHaRD3 (per scheme) and
// ViSHaRD6 (4.8 kg), a diagonal on ViSHaRD10 (diag(5, 7, 2) kg).
std::string default_shape(const std::string& device) { return device == "vishard10" ? "per-direction" : "isotropic"; }

// The schemes the thesis reports per device (issue 20's table): every inner loop, gain and feedforward setting
// on ViSHaRD3; RAC and computed torque at kp 250 on ViSHaRD6; computed torque at kp 250 on ViSHaRD10.
std::vector<std::string> default_schemes(const std::string& device) {
  if (device == "vishard6") return {"rac:250:ff", "ctc:250:ff"};
  if (device == "vishard10") return {"ctc:250:ff"};
  return {"rac:10000:ff", "rac:10000", "ijc:10000:ff", "ijc:10000", "tjc:10000:ff", "tjc:10000",
          "rac:1000:ff",  "rac:1000",  "ijc:1000:ff",  "ijc:1000",  "tjc:1000:ff",  "tjc:1000",
          "rac:250:ff",   "rac:250",   "ijc:250:ff",   "ijc:250",   "tjc:250:ff",   "tjc:250"};
}

// A direction under test: a translation along a world axis (the virtual mass) or a rotation about a handle axis
// (the virtual admittance's principal inertia is about the handle axes).
struct Direction {
  std::string name;  // x, y, z, rx, ry, rz
  bool rotation = false;
  int index = 0;
};

Direction parse_direction(const std::string& name) {
  const bool rotation = name.size() == 2;
  return {name, rotation, name.back() - 'x'};
}

// The thesis's figures (issue 20's table). ViSHaRD3: one per scheme (the worst direction, kg); ViSHaRD6: the
// translation's worst and the rotational inertia per handle axis; ViSHaRD10: per axis in both.
struct Published {
  std::optional<double> worst_kg;
  std::vector<std::pair<std::string, double>> per_direction;  // kg or kg m^2
  [[nodiscard]] std::optional<double> of(const std::string& direction) const {
    for (const auto& [d, v] : per_direction)
      if (d == direction) return v;
    return std::nullopt;
  }
};

Published published(const std::string& device, const Scheme& s) {
  Published p;
  if (device == "vishard3") {
    static const std::vector<std::pair<std::string, double>> table{
        {"tjc-kp10000-ff", 2.5}, {"tjc-kp10000", 4.2}, {"ijc-kp10000-ff", 2.6}, {"ijc-kp10000", 4.3},
        {"rac-kp10000-ff", 2.5}, {"rac-kp10000", 4.5}, {"tjc-kp1000-ff", 1.75}, {"tjc-kp1000", 2.0},
        {"ijc-kp1000-ff", 3.4},  {"ijc-kp1000", 2.8},  {"rac-kp1000-ff", 2.0},  {"rac-kp1000", 2.3}};
    for (const auto& [id, kg] : table)
      if (id == s.loop_id) p.worst_kg = kg;
  } else if (device == "vishard6" && (s.loop_id == "rac-kp250-ff" || s.loop_id == "ctc-kp250-ff")) {
    p.worst_kg = 4.8;
    p.per_direction = {{"rx", 0.005}, {"ry", 0.5}, {"rz", 0.5}};
  } else if (device == "vishard10" && s.loop_id == "ctc-kp250-ff") {
    p.worst_kg = 7.0;
    p.per_direction = {{"x", 5.0}, {"y", 7.0}, {"z", 2.0}, {"rx", 0.01}, {"ry", 0.01}, {"rz", 0.005}};
  }
  return p;
}

struct Failure {
  std::string load;
  TrialResult trial;
};

// Per direction: the bisection, and why its unstable end failed.
struct DirectionResult {
  Bisection bisection;
  Failure failure;
  int trials = 0;
};

std::string vector_line(const std::string& key, const Eigen::Vector3d& v) {
  return fmt::format("{}: [{:.17g}, {:.17g}, {:.17g}]", key, v.x(), v.y(), v.z());
}

DirectionResult bisect_direction(const Options& o, const Scheme& scheme, const Direction& direction,
                                 const Eigen::Matrix3d& handle_rotation, bool rotations,
                                 const StabilityCriterion& criterion, std::string& example_yaml) {
  const Eigen::Vector3d axis = direction.rotation ? Eigen::Vector3d(handle_rotation.col(direction.index))
                                                  : Eigen::Vector3d(Eigen::Vector3d::Unit(direction.index));
  const std::vector<OperatorLoad> loads =
      selected_loads(direction.rotation ? rotational_loads(axis) : standard_loads(axis), o.loads);
  DirectionResult result;
  double unstable_value = 0.0;
  const auto stable = [&](double value) {
    RigSpec spec;
    spec.device = rig_device(o.common);
    spec.scheme = scheme;
    spec.seed = o.common.seed;
    Eigen::Vector3d masses = Eigen::Vector3d::Constant(o.other_axes_kg);
    Eigen::Vector3d inertias = Eigen::Vector3d::Constant(o.other_axes_kg_m2);
    if (direction.rotation)
      inertias[direction.index] = value;
    else if (o.shape == "isotropic")  // run() resolves an empty shape to the device's
      masses.setConstant(value);
    else
      masses[direction.index] = value;
    spec.model = {vector_line("mass_kg", masses)};
    if (rotations) spec.model.push_back(vector_line("inertia_kg_m2", inertias));
    for (const OperatorLoad& load : loads) {
      const TrialResult trial = run_trial(spec, load, criterion);
      ++result.trials;
      if (example_yaml.empty()) example_yaml = rig_yaml(with_load(spec, load));
      if (!trial.stable) {
        // Keep the failure nearest the boundary (the largest unstable value).
        if (value >= unstable_value) {
          unstable_value = value;
          result.failure = {load.id, trial};
        }
        return false;
      }
    }
    return true;
  };
  result.bisection = direction.rotation ? smallest_stable(stable, o.low_kg_m2, o.high_kg_m2, o.tolerance)
                                        : smallest_stable(stable, o.low_kg, o.high_kg, o.tolerance);
  return result;
}

Json trial_json(const Failure& f) {
  if (f.load.empty()) return Json();
  return Json::object()
      .set("load", f.load)
      .set("oscillation_m_s", f.trial.oscillation_m_s)
      .set("oscillation_rad_s", f.trial.oscillation_rad_s)
      .set("oscillation_hz", f.trial.oscillation_hz)
      .set("fault", f.trial.fault);
}

Json optional_json(const std::optional<double>& v) { return v ? Json(*v) : Json(); }

int run(const Options& o) {
  const DevicePreset preset = device_preset(o.common.device);
  const bool rotations = preset.task != model::TaskRows::translation;
  std::vector<Scheme> schemes;
  for (const std::string& text : o.schemes.empty() ? default_schemes(o.common.device) : o.schemes) {
    Scheme s = parse_scheme(text, o.other_axes_kg);
    if (s.display != Scheme::Display::admittance)
      throw std::invalid_argument("minimum-inertia: '" + text + "' is not an admittance scheme (rac, ijc, tjc, ctc)");
    schemes.push_back(s);
  }
  std::vector<Direction> directions;
  for (const std::string& name :
       o.directions.empty() ? std::vector<std::string>{"x", "y", "z", "rx", "ry", "rz"} : o.directions) {
    const Direction d = parse_direction(name);
    if (d.rotation && !rotations) {
      if (o.directions.empty()) continue;
      throw std::invalid_argument("minimum-inertia: " + o.common.device + " renders no rotations ('" + name + "')");
    }
    directions.push_back(d);
  }
  // The rotational loads turn about the handle's axes where the rig starts.
  DeviceModel device_model(o.common.device);
  const Eigen::Matrix3d handle_rotation = device_model.handle_rotation_at(preset.rig_start());
  const StabilityCriterion criterion;
  Progress progress("minimum-inertia", schemes.size() * directions.size());
  Json list = Json::array();
  std::string example_yaml;
  std::string header = fmt::format("{:<28}", "scheme");
  for (const Direction& d : directions) header += fmt::format(" {:>9}", d.name + (d.rotation ? " [kgm2]" : " [kg]"));
  fmt::print("{} {:>14} {:>9}   {}\n", header, "worst", "thesis", "unstable near the boundary (thesis per axis)");
  for (const Scheme& scheme : schemes) {
    const Published pub = published(o.common.device, scheme);
    Json results = Json::array();
    double worst = 0.0, worst_rotation = 0.0;
    bool worst_above = false, rotation_above = false, any_rotation = false, any_translation = false;
    std::string cells, why, thesis_axes;
    for (const Direction& direction : directions) {
      const DirectionResult r =
          bisect_direction(o, scheme, direction, handle_rotation, rotations, criterion, example_yaml);
      progress.advance(scheme.loop_id + " " + direction.name);
      const Bisection& b = r.bisection;
      const std::optional<double> thesis = pub.of(direction.name);
      results.push(Json::object()
                       .set("direction", direction.name)
                       .set("quantity", direction.rotation ? "inertia" : "mass")
                       .set("unit", direction.rotation ? "kg m^2" : "kg")
                       .set("minimum", b.above_range ? Json() : Json(b.value))
                       .set("largest_unstable", b.unstable > 0.0 ? Json(b.unstable) : Json())
                       .set("below_range", b.below_range)
                       .set("above_range", b.above_range)
                       .set("published", optional_json(thesis))
                       .set("trials", r.trials)
                       .set("unstable", trial_json(r.failure)));
      if (direction.rotation) {
        any_rotation = true;
        worst_rotation = std::max(worst_rotation, b.value);
        rotation_above = rotation_above || b.above_range;
      } else {
        any_translation = true;
        worst = std::max(worst, b.value);
        worst_above = worst_above || b.above_range;
      }
      const double high = direction.rotation ? o.high_kg_m2 : o.high_kg;
      cells += b.above_range ? fmt::format(" {:>9}", fmt::format(">{:g}", high))
                             : fmt::format(" {:>9.{}f}", b.value, direction.rotation ? 3 : 2);
      if (thesis) thesis_axes += fmt::format("{}{} {:g}", thesis_axes.empty() ? "" : ", ", direction.name, *thesis);
      if (!r.failure.load.empty()) {
        why += fmt::format(
            "{}{}: {} ({})", why.empty() ? "" : "; ", direction.name, r.failure.load,
            r.failure.trial.fault.empty() ? fmt::format("{:.0f} Hz", r.failure.trial.oscillation_hz) : "fault");
      }
    }
    std::string worst_cell = !any_translation ? std::string("-")
                             : worst_above    ? fmt::format(">{:g}", o.high_kg)
                                              : fmt::format("{:.2f}", worst);
    if (any_rotation)
      worst_cell += rotation_above ? fmt::format(" / >{:g}", o.high_kg_m2) : fmt::format(" / {:.3f}", worst_rotation);
    fmt::print("{:<28}{} {:>14} {:>9}   {}{}\n", scheme.loop_label, cells, worst_cell,
               pub.worst_kg ? fmt::format("{:g}", *pub.worst_kg) : std::string("-"), why,
               thesis_axes.empty() ? "" : " (thesis: " + thesis_axes + ")");
    list.push(Json::object()
                  .set("id", scheme.loop_id)
                  .set("label", scheme.loop_label)
                  .set("worst_kg", !any_translation || worst_above ? Json() : Json(worst))
                  .set("worst_kg_m2", !any_rotation || rotation_above ? Json() : Json(worst_rotation))
                  .set("published_kg", optional_json(pub.worst_kg))
                  .set("directions", results));
  }
  const Json loads = loads_json(selected_loads(standard_loads(Eigen::Vector3d::UnitX()), o.loads));
  const Json rotational = loads_json(rotations ? selected_loads(rotational_loads(Eigen::Vector3d::UnitX()), o.loads)
                                               : std::vector<OperatorLoad>{});
  Json result = Json::object();
  result.set("experiment", "minimum-inertia")
      .set("title", "Minimum virtual inertia (admittance display, pure mass)")
      .set("device", o.common.device)
      .set("criterion", criterion_json(criterion))
      .set("loads", loads)
      .set("rotational_loads", rotational)
      .set("range_kg", std::vector<double>{o.low_kg, o.high_kg})
      .set("range_kg_m2", std::vector<double>{o.low_kg_m2, o.high_kg_m2})
      .set("tolerance", o.tolerance)
      .set("shape", o.shape)
      .set("other_axes_kg", o.other_axes_kg)
      .set("other_axes_kg_m2", o.other_axes_kg_m2)
      .set("schemes", list)
      .set("command", command_line())
      .set("example_session", example_yaml);
  publish_result(o.common.report(), "minimum-inertia", result);
  return 0;
}

}  // namespace

void add_minimum_inertia_command(CLI::App& app, int& exit_code) {
  auto o = command_options<Options>();
  CLI::App* cmd = app.add_subcommand(
      "minimum-inertia",
      "Bisection of the smallest pure virtual mass each admittance scheme renders stably, per direction, under "
      "the standardized operator loads");
  add_common_options(cmd, o->common, {"vishard3", "vishard6", "vishard10"});
  cmd->add_option("--schemes", o->schemes,
                  "admittance schemes: rac:KP[:ff], ijc:KP[:ff], tjc:KP[:ff], ctc:KP[:ff] (computed torque on the "
                  "device's inverse kinematics); default: the thesis's for the device (vishard3: RAC, IJC, TJC at kp "
                  "10000, 1000, 250 with and without feedforward; vishard6: rac:250:ff ctc:250:ff; vishard10: "
                  "ctc:250:ff)");
  cmd->add_option("--directions", o->directions,
                  "directions under test: translation along the world axes, rotation (rx, ry, rz) about the handle "
                  "axes; default: x y z, and rx ry rz on devices that render rotations")
      ->check(CLI::IsMember({"x", "y", "z", "rx", "ry", "rz"}));
  cmd->add_option("--loads", o->loads, "operator loads (a mass is stable when it is under every one)")
      ->check(CLI::IsMember({"firm-grasp", "loose-grasp", "voluntary-motion", "wall-collision"}))
      ->capture_default_str();
  cmd->add_option("--shape", o->shape,
                  "the translational mass: per-direction (the mass under test on its own axis, the others 10 kg) "
                  "or isotropic (the same mass on every axis, a pure mass m I, pushed along each direction); "
                  "default: as the thesis reports the device (vishard3, vishard6: isotropic; vishard10: "
                  "per-direction); rotations are always per direction, the others at 1 kg m^2")
      ->check(CLI::IsMember({"per-direction", "isotropic"}));
  cmd->add_option("--low", o->low_kg, "the bisection's lower end [kg]")
      ->check(CLI::Range(0.01, 100.0))
      ->capture_default_str();
  cmd->add_option("--high", o->high_kg, "the bisection's upper end [kg]")
      ->check(CLI::Range(0.1, 1000.0))
      ->capture_default_str();
  cmd->add_option("--low-inertia", o->low_kg_m2, "the rotational bisection's lower end [kg m^2]")
      ->check(CLI::Range(1e-5, 10.0))
      ->capture_default_str();
  cmd->add_option("--high-inertia", o->high_kg_m2, "the rotational bisection's upper end [kg m^2]")
      ->check(CLI::Range(1e-3, 100.0))
      ->capture_default_str();
  cmd->add_option("--tolerance", o->tolerance, "relative width of the final bracket")
      ->check(CLI::Range(0.001, 1.0))
      ->capture_default_str();
  cmd->callback([o, &exit_code] {
    Options run_options = *o;
    if (run_options.shape.empty()) run_options.shape = default_shape(run_options.common.device);
    if (run_options.common.quick) {  // one scheme, one direction, a coarse bracket
      if (run_options.schemes.empty()) run_options.schemes = default_schemes(run_options.common.device);
      run_options.schemes.resize(1);
      if (run_options.directions.empty()) run_options.directions = {"x"};
      run_options.directions.resize(1);
      run_options.tolerance = std::max(run_options.tolerance, 0.3);
    }
    if (!(run_options.low_kg < run_options.high_kg)) throw CLI::ValidationError("--low", "must be below --high");
    if (!(run_options.low_kg_m2 < run_options.high_kg_m2))
      throw CLI::ValidationError("--low-inertia", "must be below --high-inertia");
    exit_code = run(run_options);
  });
}

}  // namespace hapticd::eval
