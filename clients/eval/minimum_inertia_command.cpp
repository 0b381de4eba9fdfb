#include "minimum_inertia_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <optional>

#include "analysis/stability.hpp"
#include "eval_options.hpp"
#include "experiment/rig.hpp"
#include "experiment/stability_trial.hpp"
#include "report/progress.hpp"

namespace hapticd::eval {
namespace {

struct Options {
  CommonOptions common;
  std::vector<std::string> schemes{"rac:10000:ff", "rac:10000",   "ijc:10000:ff", "ijc:10000",   "tjc:10000:ff",
                                   "tjc:10000",    "rac:1000:ff", "rac:1000",     "ijc:1000:ff", "ijc:1000",
                                   "tjc:1000:ff",  "tjc:1000",    "rac:250:ff",   "rac:250",     "ijc:250:ff",
                                   "ijc:250",      "tjc:250:ff",  "tjc:250"};
  std::vector<std::string> directions{"x", "y", "z"};
  std::vector<std::string> loads{"firm-grasp", "loose-grasp", "voluntary-motion", "wall-collision"};
  double low_kg = 0.2, high_kg = 20.0, tolerance = 0.05;
  double other_axes_kg = 10.0;  // the mass of the directions not under test
};

// The thesis's figures for ViSHaRD3 (kg; issue 20's table): with / without feedforward.
std::optional<double> published(const Scheme& s) {
  static const std::vector<std::pair<std::string, double>> table{
      {"tjc-kp10000-ff", 2.5}, {"tjc-kp10000", 4.2}, {"ijc-kp10000-ff", 2.6}, {"ijc-kp10000", 4.3},
      {"rac-kp10000-ff", 2.5}, {"rac-kp10000", 4.5}, {"tjc-kp1000-ff", 1.75}, {"tjc-kp1000", 2.0},
      {"ijc-kp1000-ff", 3.4},  {"ijc-kp1000", 2.8},  {"rac-kp1000-ff", 2.0},  {"rac-kp1000", 2.3}};
  for (const auto& [id, kg] : table)
    if (id == s.loop_id) return kg;
  return std::nullopt;
}

Eigen::Vector3d axis_of(const std::string& name) {
  if (name == "x") return Eigen::Vector3d::UnitX();
  if (name == "y") return Eigen::Vector3d::UnitY();
  return Eigen::Vector3d::UnitZ();
}

struct Failure {
  std::string load;
  TrialResult trial;
};

// Per direction: the bisection, and why its unstable end failed.
struct DirectionResult {
  std::string direction;
  Bisection bisection;
  Failure failure;
  int trials = 0;
};

DirectionResult bisect_direction(const Options& o, const Scheme& scheme, const std::string& direction,
                                 const StabilityCriterion& criterion, std::string& example_yaml) {
  const Eigen::Vector3d d = axis_of(direction);
  std::vector<OperatorLoad> loads;
  for (const OperatorLoad& load : standard_loads(d))
    if (std::find(o.loads.begin(), o.loads.end(), load.id) != o.loads.end()) loads.push_back(load);
  DirectionResult result{direction, {}, {}, 0};
  double unstable_mass = 0.0;
  const auto stable = [&](double mass) {
    RigSpec spec;
    spec.device.name = o.common.device;
    spec.device.sim_parameters = o.common.sim_parameters;
    spec.scheme = scheme;
    spec.seed = o.common.seed;
    Eigen::Vector3d masses = Eigen::Vector3d::Constant(o.other_axes_kg);
    masses[direction == "x" ? 0 : direction == "y" ? 1 : 2] = mass;
    spec.model = {fmt::format("mass_kg: [{:.17g}, {:.17g}, {:.17g}]", masses.x(), masses.y(), masses.z())};
    for (const OperatorLoad& load : loads) {
      const TrialResult trial = run_trial(spec, load, criterion);
      ++result.trials;
      if (example_yaml.empty()) example_yaml = rig_yaml(with_load(spec, load));
      if (!trial.stable) {
        // Keep the failure nearest the boundary (the largest unstable mass).
        if (mass >= unstable_mass) {
          unstable_mass = mass;
          result.failure = {load.id, trial};
        }
        return false;
      }
    }
    return true;
  };
  result.bisection = smallest_stable(stable, o.low_kg, o.high_kg, o.tolerance);
  return result;
}

Json trial_json(const Failure& f) {
  if (f.load.empty()) return Json();
  return Json::object()
      .set("load", f.load)
      .set("oscillation_m_s", f.trial.oscillation_m_s)
      .set("oscillation_hz", f.trial.oscillation_hz)
      .set("fault", f.trial.fault);
}

int run(const Options& o) {
  std::vector<Scheme> schemes;
  for (const std::string& text : o.schemes) {
    Scheme s = parse_scheme(text, o.other_axes_kg);
    if (s.display != Scheme::Display::admittance)
      throw std::invalid_argument("minimum-inertia: '" + text + "' is not an admittance scheme (rac, ijc, tjc)");
    schemes.push_back(s);
  }
  const StabilityCriterion criterion;
  Progress progress("minimum-inertia", schemes.size() * o.directions.size());
  Json list = Json::array();
  std::string example_yaml;
  fmt::print("{:<32} {:>10} {:>10} {:>10} {:>10} {:>10}   {}\n", "scheme", "x [kg]", "y [kg]", "z [kg]", "worst",
             "thesis", "unstable near the boundary");
  for (const Scheme& scheme : schemes) {
    Json directions = Json::array();
    double worst = 0.0;
    bool worst_above = false;
    std::string cells, why;
    for (const std::string& direction : {std::string("x"), std::string("y"), std::string("z")}) {
      if (std::find(o.directions.begin(), o.directions.end(), direction) == o.directions.end()) {
        cells += fmt::format(" {:>10}", "-");
        continue;
      }
      const DirectionResult r = bisect_direction(o, scheme, direction, criterion, example_yaml);
      progress.advance(scheme.loop_id + " " + direction);
      const Bisection& b = r.bisection;
      directions.push(Json::object()
                          .set("direction", direction)
                          .set("minimum_kg", b.above_range ? Json() : Json(b.value))
                          .set("largest_unstable_kg", b.unstable > 0.0 ? Json(b.unstable) : Json())
                          .set("below_range", b.below_range)
                          .set("above_range", b.above_range)
                          .set("trials", r.trials)
                          .set("unstable", trial_json(r.failure)));
      worst = std::max(worst, b.value);
      worst_above = worst_above || b.above_range;
      cells +=
          b.above_range ? fmt::format(" {:>10}", fmt::format(">{:g}", o.high_kg)) : fmt::format(" {:>10.2f}", b.value);
      if (!r.failure.load.empty()) {
        why += fmt::format(
            "{}{}: {} ({})", why.empty() ? "" : "; ", direction, r.failure.load,
            r.failure.trial.fault.empty() ? fmt::format("{:.0f} Hz", r.failure.trial.oscillation_hz) : "fault");
      }
    }
    const std::optional<double> pub = published(scheme);
    fmt::print("{:<32}{} {:>10} {:>10}   {}\n", scheme.loop_label, cells,
               worst_above ? fmt::format(">{:g}", o.high_kg) : fmt::format("{:.2f}", worst),
               pub ? fmt::format("{:g}", *pub) : std::string("-"), why);
    list.push(Json::object()
                  .set("id", scheme.loop_id)
                  .set("label", scheme.loop_label)
                  .set("worst_kg", worst_above ? Json() : Json(worst))
                  .set("published_kg", pub ? Json(*pub) : Json())
                  .set("directions", directions));
  }
  Json loads = Json::array();
  for (const OperatorLoad& load : standard_loads(Eigen::Vector3d::UnitX()))
    if (std::find(o.loads.begin(), o.loads.end(), load.id) != o.loads.end())
      loads.push(Json::object().set("id", load.id).set("label", load.label));
  Json result = Json::object();
  result.set("experiment", "minimum-inertia")
      .set("title", "Minimum virtual inertia (admittance display, pure mass)")
      .set("device", o.common.device)
      .set("criterion", Json::object()
                            .set("duration_s", criterion.duration_s)
                            .set("window_s", criterion.window_s)
                            .set("cutoff_hz", criterion.cutoff_hz)
                            .set("threshold_m_s", criterion.threshold_m_s)
                            .set("collision_tolerance_j", criterion.collision_tolerance_j))
      .set("loads", loads)
      .set("range_kg", std::vector<double>{o.low_kg, o.high_kg})
      .set("tolerance", o.tolerance)
      .set("other_axes_kg", o.other_axes_kg)
      .set("schemes", list)
      .set("command", command_line())
      .set("example_session", example_yaml);
  publish_result(o.common.report(), "minimum-inertia", result);
  return 0;
}

}  // namespace

void add_minimum_inertia_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "minimum-inertia",
      "Bisection of the smallest pure virtual mass each admittance scheme renders stably, per direction, under "
      "the standardized operator loads");
  add_common_options(cmd, o->common);
  cmd->add_option("--schemes", o->schemes, "admittance schemes: rac:KP[:ff], ijc:KP[:ff], tjc:KP[:ff]")
      ->capture_default_str();
  cmd->add_option("--directions", o->directions, "directions under test")
      ->check(CLI::IsMember({"x", "y", "z"}))
      ->capture_default_str();
  cmd->add_option("--loads", o->loads, "operator loads (a mass is stable when it is under every one)")
      ->check(CLI::IsMember({"firm-grasp", "loose-grasp", "voluntary-motion", "wall-collision"}))
      ->capture_default_str();
  cmd->add_option("--low", o->low_kg, "the bisection's lower end [kg]")
      ->check(CLI::Range(0.01, 100.0))
      ->capture_default_str();
  cmd->add_option("--high", o->high_kg, "the bisection's upper end [kg]")
      ->check(CLI::Range(0.1, 1000.0))
      ->capture_default_str();
  cmd->add_option("--tolerance", o->tolerance, "relative width of the final bracket")
      ->check(CLI::Range(0.001, 1.0))
      ->capture_default_str();
  cmd->callback([o, &exit_code] {
    Options run_options = *o;
    if (run_options.common.quick) {  // one scheme, one direction, a coarse bracket
      run_options.schemes.resize(1);
      run_options.directions = {"x"};
      run_options.tolerance = std::max(run_options.tolerance, 0.3);
    }
    if (!(run_options.low_kg < run_options.high_kg)) throw CLI::ValidationError("--low", "must be below --high");
    exit_code = run(run_options);
  });
}

}  // namespace hapticd::eval
