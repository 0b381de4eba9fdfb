#include "force_gain_command.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "analysis/stability.hpp"
#include "eval_options.hpp"
#include "experiment/rig.hpp"
#include "experiment/stability_trial.hpp"
#include "report/progress.hpp"

namespace hapticd::eval {
namespace {

// The thesis ran impedance display with PD force feedback up to Kp 3.75 on ViSHaRD3 (issue 20's table).
constexpr double kPublishedKp = 3.75;

struct Options {
  CommonOptions common;
  double kd = 0.003;
  std::vector<std::string> directions{"x", "y", "z"};
  std::vector<std::string> loads{"firm-grasp", "loose-grasp", "voluntary-motion", "wall-collision"};
  double low = 0.1, high = 50.0, tolerance = 0.05;  // 50: the impedance controller's largest force_gain
};

int run(const Options& o) {
  const StabilityCriterion criterion;
  Progress progress("force-gain", o.directions.size());
  Json directions = Json::array();
  std::string example_yaml;
  double worst = o.high;
  bool any_below = false;
  fmt::print("{:<10} {:>12} {:>16}   {}\n", "direction", "largest Kp", "unstable above", "unstable near the boundary");
  for (const std::string& name : o.directions) {
    const Eigen::Vector3d axis = Eigen::Vector3d::Unit(name[0] - 'x');
    const std::vector<OperatorLoad> loads = selected_loads(standard_loads(axis), o.loads);
    std::string failed_load;
    TrialResult failed;
    double failed_kp = 0.0;
    int trials = 0;
    const auto stable = [&](double kp) {
      RigSpec spec;
      spec.device = rig_device(o.common);
      spec.scheme = pd_force_feedback(kp, o.kd);
      spec.seed = o.common.seed;
      for (const OperatorLoad& load : loads) {
        const TrialResult trial = run_trial(spec, load, criterion);
        ++trials;
        if (example_yaml.empty()) example_yaml = rig_yaml(with_load(spec, load));
        if (!trial.stable) {
          // Keep the failure nearest the boundary (the smallest unstable gain).
          if (failed_load.empty() || kp <= failed_kp) {
            failed_kp = kp;
            failed_load = load.id;
            failed = trial;
          }
          return false;
        }
      }
      return true;
    };
    const Bisection b = largest_stable(stable, o.low, o.high, o.tolerance);
    progress.advance(name);
    const std::string why =
        failed_load.empty()
            ? std::string("-")
            : fmt::format("{} ({})", failed_load,
                          failed.fault.empty() ? fmt::format("{:.0f} Hz", failed.oscillation_hz) : failed.fault);
    fmt::print("{:<10} {:>12} {:>16}   {}\n", name,
               b.below_range   ? fmt::format("<{:g}", o.low)
               : b.above_range ? fmt::format(">{:g}", o.high)
                               : fmt::format("{:.2f}", b.value),
               b.above_range ? std::string("-") : fmt::format("{:.2f}", b.unstable), why);
    Json unstable;
    if (!failed_load.empty()) {
      unstable = Json::object()
                     .set("load", failed_load)
                     .set("oscillation_m_s", failed.oscillation_m_s)
                     .set("oscillation_hz", failed.oscillation_hz)
                     .set("fault", failed.fault);
    }
    directions.push(Json::object()
                        .set("direction", name)
                        .set("largest_kp", b.below_range ? Json() : Json(b.value))
                        .set("smallest_unstable_kp", b.above_range ? Json() : Json(b.unstable))
                        .set("below_range", b.below_range)
                        .set("above_range", b.above_range)
                        .set("trials", trials)
                        .set("unstable", unstable));
    worst = std::min(worst, b.value);
    any_below = any_below || b.below_range;
  }
  fmt::print("worst direction: Kp {}; thesis: stable up to {:g}\n",
             any_below ? fmt::format("<{:g}", o.low) : fmt::format("{:.2f}", worst), kPublishedKp);
  Json result = Json::object();
  result.set("experiment", "force-gain")
      .set("title", "Largest stable force-feedback gain (impedance display, PD force feedback)")
      .set("device", o.common.device)
      .set("kd", o.kd)
      .set("criterion", criterion_json(criterion))
      .set("loads", loads_json(selected_loads(standard_loads(Eigen::Vector3d::UnitX()), o.loads)))
      .set("range", std::vector<double>{o.low, o.high})
      .set("tolerance", o.tolerance)
      .set("directions", directions)
      .set("worst_kp", any_below ? Json() : Json(worst))
      .set("published_kp", kPublishedKp)
      .set("command", command_line())
      .set("example_session", example_yaml);
  publish_result(o.common.report(), "force-gain", result);
  return 0;
}

}  // namespace

void add_force_gain_command(CLI::App& app, int& exit_code) {
  auto o = command_options<Options>();
  CLI::App* cmd = app.add_subcommand(
      "force-gain",
      "Bisection of the largest force-feedback gain Kp impedance display (PD force feedback) renders stably, per "
      "direction, under the standardized operator loads");
  add_common_options(cmd, o->common);
  cmd->add_option("--kd", o->kd, "the force feedback's derivative gain [s]")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--directions", o->directions, "directions under test")
      ->check(CLI::IsMember({"x", "y", "z"}))
      ->capture_default_str();
  cmd->add_option("--loads", o->loads, "operator loads (a gain is stable when it is under every one)")
      ->check(CLI::IsMember({"firm-grasp", "loose-grasp", "voluntary-motion", "wall-collision"}))
      ->capture_default_str();
  cmd->add_option("--low", o->low, "the bisection's lower end")->check(CLI::Range(0.01, 100.0))->capture_default_str();
  cmd->add_option("--high", o->high, "the bisection's upper end")
      ->check(CLI::Range(0.1, 1000.0))
      ->capture_default_str();
  cmd->add_option("--tolerance", o->tolerance, "relative width of the final bracket")
      ->check(CLI::Range(0.001, 1.0))
      ->capture_default_str();
  cmd->callback([o, &exit_code] {
    Options run_options = *o;
    if (run_options.common.quick) {  // one direction, a coarse bracket
      run_options.directions.resize(1);
      run_options.tolerance = std::max(run_options.tolerance, 0.3);
    }
    if (!(run_options.low < run_options.high)) throw CLI::ValidationError("--low", "must be below --high");
    exit_code = run(run_options);
  });
}

}  // namespace hapticd::eval
