#include "z_width_command.hpp"

#include <fmt/format.h>

#include "analysis/stability.hpp"
#include "eval_options.hpp"
#include "experiment/rig.hpp"
#include "experiment/stability_trial.hpp"
#include "report/progress.hpp"

namespace hapticd::eval {
namespace {

struct Options {
  CommonOptions common;
  std::vector<std::string> schemes{"open-loop", "pd:1.5:0.003", "rac:10000:ff", "rac:1000:ff", "tjc:10000:ff"};
  // Above every ViSHaRD3 scheme's smallest stable pure mass under the firm grasp (3.96 kg, minimum-inertia): a
  // lighter display oscillates with the passivity experiment's firm grasp whatever the wall, and the Z-width
  // would measure that instead of the wall.
  double virtual_mass_kg = 5.0;
  std::vector<double> wall_damping{0.0, 20.0, 50.0, 100.0, 200.0};
  // Admittance display: the renderable mass-damping-stiffness space (virtual mass x virtual damping).
  std::vector<double> mbk_masses{1.0, 3.0, 10.0};
  std::vector<double> mbk_dampings{0.0, 20.0, 100.0};
  std::string direction = "x";
  double low = 100.0, high = 1e6, tolerance = 0.1;
  // Colgate's passivity experiment: the position source's frequencies (whole periods at 2 kHz).
  std::vector<double> frequencies_hz{2.0, 5.0, 10.0, 20.0, 40.0};
};

// The largest wall stiffness the rig renders with the given wall damping: passive (the port absorbs energy at
// every test frequency of port_energy) and stable in collisions with a loose and a firm grasp (no fault, the
// operator never gets back more energy than it gave).
struct Boundary {
  Bisection bisection;
  std::string why;  // what failed at the bracket's unstable end
  int trials = 0;
};

Boundary largest_wall(const Options& o, const RigSpec& base, double wall_damping, std::string& example_yaml) {
  const Eigen::Vector3d d = o.direction == "x"   ? Eigen::Vector3d::UnitX()
                            : o.direction == "y" ? Eigen::Vector3d::UnitY()
                                                 : Eigen::Vector3d::UnitZ();
  const StabilityCriterion criterion;
  Boundary b;
  double failed_at = 0.0;
  const auto fail = [&](double stiffness, std::string why) {
    if (failed_at == 0.0 || stiffness < failed_at) {  // the failure nearest the boundary
      failed_at = stiffness;
      b.why = std::move(why);
    }
    return false;
  };
  const auto holds = [&](double stiffness) {
    const WallSpec wall{stiffness, wall_damping};
    for (const double f : o.frequencies_hz) {
      const PassivityResult p = port_energy(base, d, wall, f);
      ++b.trials;
      if (!p.fault.empty()) return fail(stiffness, fmt::format("{:g} Hz: fault {}", f, p.fault));
      if (p.energy_per_period_j < 0.0)
        return fail(stiffness, fmt::format("{:g} Hz: gives out {:.2e} J per period", f, -p.energy_per_period_j));
    }
    for (const double grasp : {0.0, 1.0}) {
      const OperatorLoad load = wall_collision(d, grasp, wall);
      const TrialResult t = run_trial(base, load, criterion);
      ++b.trials;
      if (example_yaml.empty()) example_yaml = rig_yaml(with_load(base, load));
      if (!t.fault.empty()) return fail(stiffness, fmt::format("collision, grasp {:g}: fault {}", grasp, t.fault));
      if (!t.stable) {
        return fail(stiffness, fmt::format("collision, grasp {:g}: gives back {:.3f} J more than it took ({:.0f} Hz)",
                                           grasp, -t.least_operator_work_j, t.oscillation_hz));
      }
    }
    return true;
  };
  b.bisection = largest_stable(holds, o.low, o.high, o.tolerance);
  return b;
}

Json boundary_json(const Boundary& b, const std::string& key, double value) {
  return Json::object()
      .set(key, value)
      .set("stiffness_n_per_m", b.bisection.below_range ? Json(0.0) : Json(b.bisection.value))
      .set("above_range", b.bisection.above_range)
      .set("limited_by", b.why)
      .set("trials", b.trials);
}

int run(const Options& o) {
  std::vector<Scheme> schemes;
  for (const std::string& text : o.schemes) schemes.push_back(parse_scheme(text, o.virtual_mass_kg));
  std::size_t units = 0;
  for (const Scheme& s : schemes)
    units += o.wall_damping.size() +
             (s.display == Scheme::Display::admittance ? o.mbk_masses.size() * o.mbk_dampings.size() : 0);
  Progress progress("z-width", units);
  std::string example_yaml;
  Json list = Json::array();
  fmt::print("largest stable and passive wall stiffness [N/m] along {} per wall damping [N s/m]\n", o.direction);
  fmt::print("{:<36}", "scheme");
  for (double b : o.wall_damping) fmt::print(" {:>10}", fmt::format("B={:g}", b));
  fmt::print("\n");
  for (const Scheme& scheme : schemes) {
    RigSpec base;
    base.device = rig_device(o.common);
    base.scheme = scheme;
    base.seed = o.common.seed;
    Json region = Json::array();
    fmt::print("{:<36}", scheme.label.substr(0, 36));
    for (const double damping : o.wall_damping) {
      const Boundary b = largest_wall(o, base, damping, example_yaml);
      progress.advance(fmt::format("{} B {:g}", scheme.id, damping));
      region.push(boundary_json(b, "wall_damping_n_s_per_m", damping));
      fmt::print(" {:>10}", b.bisection.above_range   ? fmt::format(">{:g}", o.high)
                            : b.bisection.below_range ? fmt::format("<{:g}", o.low)
                                                      : fmt::format("{:.0f}", b.bisection.value));
    }
    fmt::print("\n");
    Json entry = Json::object().set("id", scheme.id).set("label", scheme.label).set("region", region);
    if (scheme.display == Scheme::Display::admittance && !o.mbk_masses.empty()) {
      Json space = Json::array();
      for (const double mass : o.mbk_masses) {
        for (const double damping : o.mbk_dampings) {
          RigSpec spec = base;
          spec.model = {fmt::format("mass_kg: [{0:.17g}, {0:.17g}, {0:.17g}]", mass),
                        fmt::format("damping_n_s_per_m: [{0:.17g}, {0:.17g}, {0:.17g}]", damping)};
          const Boundary b = largest_wall(o, spec, 0.0, example_yaml);
          progress.advance(fmt::format("{} M {:g} B {:g}", scheme.loop_id, mass, damping));
          space.push(boundary_json(b, "virtual_damping_n_s_per_m", damping).set("virtual_mass_kg", mass));
          fmt::print("  {} M {:g} kg, B {:g} N s/m: K {}\n", scheme.loop_label, mass, damping,
                     b.bisection.above_range   ? fmt::format("> {:g}", o.high)
                     : b.bisection.below_range ? fmt::format("< {:g}", o.low)
                                               : fmt::format("{:.0f} N/m", b.bisection.value));
        }
      }
      entry.set("mass_damping_stiffness", space);
    }
    list.push(entry);
  }
  Json result = Json::object();
  result.set("experiment", "z-width")
      .set("title", "Z-width: the virtual walls rendered stably and passively")
      .set("device", o.common.device)
      .set("direction", o.direction)
      .set("virtual_mass_kg", o.virtual_mass_kg)
      .set("range_n_per_m", std::vector<double>{o.low, o.high})
      .set("frequencies_hz", o.frequencies_hz)
      .set("energy_tolerance_j", StabilityCriterion{}.collision_tolerance_j)
      .set("schemes", list)
      .set("command", command_line())
      .set("example_session", example_yaml);
  publish_result(o.common.report(), "z-width", result);
  return 0;
}

}  // namespace

void add_z_width_command(CLI::App& app, int& exit_code) {
  auto o = command_options<Options>();
  CLI::App* cmd = app.add_subcommand(
      "z-width",
      "The virtual walls (stiffness per damping) each scheme renders stably and passively under collisions with "
      "a loose and a firm grasp; for admittance display also the renderable mass-damping-stiffness space");
  add_common_options(cmd, o->common);
  add_scheme_options(cmd, o->schemes, o->virtual_mass_kg);
  cmd->add_option("--wall-damping", o->wall_damping, "the wall dampings of the region [N s/m]")->capture_default_str();
  cmd->add_option("--masses", o->mbk_masses, "admittance display: the virtual masses of the M-B-K space [kg]")
      ->capture_default_str();
  cmd->add_option("--dampings", o->mbk_dampings, "admittance display: the virtual dampings of the M-B-K space")
      ->capture_default_str();
  cmd->add_option("--frequencies", o->frequencies_hz, "the passivity experiment's frequencies [Hz]")
      ->check(CLI::Range(0.1, 200.0))
      ->capture_default_str();
  cmd->add_option("--direction", o->direction, "the wall's normal")
      ->check(CLI::IsMember({"x", "y", "z"}))
      ->capture_default_str();
  cmd->add_option("--tolerance", o->tolerance, "relative width of the final bracket")
      ->check(CLI::Range(0.001, 1.0))
      ->capture_default_str();
  cmd->callback([o, &exit_code] {
    Options run_options = *o;
    if (run_options.common.quick) {
      run_options.schemes = {"open-loop", "rac:10000:ff"};
      run_options.wall_damping = {0.0, 100.0};
      run_options.mbk_masses = {5.0};
      run_options.mbk_dampings = {0.0};
      run_options.frequencies_hz = {10.0};
      run_options.tolerance = std::max(run_options.tolerance, 0.5);
    }
    exit_code = run(run_options);
  });
}

}  // namespace hapticd::eval
