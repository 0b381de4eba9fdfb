#include "backdrivability_command.hpp"

#include <fmt/format.h>

#include <cmath>

#include "eval_options.hpp"
#include "experiment/rig.hpp"
#include "report/progress.hpp"

namespace hapticd::eval {
namespace {

struct Options {
  CommonOptions common;
  std::vector<std::string> schemes{"open-loop", "pd:1.5:0.003", "rac:500:ff", "ijc:500:ff", "tjc:500:ff"};
  double virtual_mass_kg = 5.0;
  double distance_m = 0.15, acceleration_m_s2 = 3.0, speed_m_s = 0.3;
  int legs = 4;  // out and back twice
};

constexpr double kRate = 2000.0;
constexpr double kPathStart = 0.5;   // the device settles before the guide moves
constexpr int kPlotDecimation = 10;  // 200 samples per second in the report

struct SchemeRun {
  Scheme scheme;
  std::vector<double> time, velocity, acceleration, error;
  double rms = 0.0, peak = 0.0;
  std::string fault;
};

SchemeRun run_scheme(const Options& o, const Scheme& scheme, std::string& example_yaml) {
  RigSpec spec;
  spec.device = rig_device(o.common);
  spec.scheme = scheme;
  spec.seed = o.common.seed;
  spec.attachment = {"attachment: position_source",
                     "source_path: shuttle",
                     fmt::format("source_path_m: [{:.17g}, 0, 0]", o.distance_m),
                     fmt::format("source_path_start_s: {}", kPathStart),
                     fmt::format("source_path_acceleration: {:.17g}", o.acceleration_m_s2),
                     fmt::format("source_path_speed: {:.17g}", o.speed_m_s)};
  if (example_yaml.empty()) example_yaml = rig_yaml(spec);
  server::Session session = make_rig_session(spec);
  const double leg_s = shuttle_leg_s(o.distance_m, o.acceleration_m_s2, o.speed_m_s);
  const double end_s = kPathStart + o.legs * leg_s;
  const auto cycles = static_cast<std::uint64_t>(std::ceil(end_s * kRate));
  SchemeRun run{scheme, {}, {}, {}, {}, 0.0, 0.0, {}};
  const bool admittance = scheme.display == Scheme::Display::admittance;
  double previous_velocity = 0.0, previous_t = 0.0, sum = 0.0;
  std::size_t n = 0, k = 0;
  run.fault = run_rig(session, cycles, [&](const RigSample& s) {
    const double vx = s.true_velocity.x();
    const double ax = k > 0 ? (vx - previous_velocity) / (s.t - previous_t) : 0.0;
    previous_velocity = vx;
    previous_t = s.t;
    // The force the device puts on the guide beyond what it should: nothing in impedance display (free space),
    // the virtual mass's inertial force in admittance display: F_err = F_m + m a_m [5.1].
    const double error = s.measured_force.x() + (admittance ? scheme.virtual_mass_kg * ax : 0.0);
    if (s.t >= kPathStart) {
      sum += error * error;
      run.peak = std::max(run.peak, std::abs(error));
      ++n;
      if (k % kPlotDecimation == 0) {
        run.time.push_back(s.t);
        run.velocity.push_back(vx);
        run.acceleration.push_back(ax);
        run.error.push_back(error);
      }
    }
    ++k;
  });
  run.rms = n > 0 ? std::sqrt(sum / static_cast<double>(n)) : 0.0;
  return run;
}

int run(const Options& o) {
  std::vector<Scheme> schemes;
  for (const std::string& text : o.schemes) schemes.push_back(parse_scheme(text, o.virtual_mass_kg));
  Progress progress("backdrivability", schemes.size());
  std::vector<SchemeRun> runs;
  std::string example_yaml;
  for (const Scheme& s : schemes) {
    runs.push_back(run_scheme(o, s, example_yaml));
    progress.advance(s.id);
  }
  Json result = Json::object();
  result.set("experiment", "backdrivability")
      .set("title", "Backdrivability (the handle driven by a stiff guide along x)")
      .set("device", o.common.device)
      .set("virtual_mass_kg", o.virtual_mass_kg)
      .set("path", Json::object()
                       .set("distance_m", o.distance_m)
                       .set("acceleration_m_s2", o.acceleration_m_s2)
                       .set("speed_m_s", o.speed_m_s)
                       .set("legs", o.legs))
      .set("command", command_line());
  Json list = Json::array();
  fmt::print("{:<36} {:>14} {:>14}\n", "scheme", "RMS error", "peak error");
  const SchemeRun* open_loop = nullptr;
  for (const SchemeRun& r : runs) {
    list.push(Json::object()
                  .set("id", r.scheme.id)
                  .set("label", r.scheme.label)
                  .set("rms_error_n", r.rms)
                  .set("peak_error_n", r.peak)
                  .set("fault", r.fault)
                  .set("time_s", r.time)
                  .set("velocity_m_s", r.velocity)
                  .set("acceleration_m_s2", r.acceleration)
                  .set("force_error_n", r.error));
    fmt::print("{:<36} {:>12.2f} N {:>12.2f} N{}\n", r.scheme.label, r.rms, r.peak,
               r.fault.empty() ? "" : "   FAULT: " + r.fault);
    if (r.scheme.id == "open-loop") open_loop = &r;
  }
  result.set("schemes", list);
  // The model's prediction for PD force feedback: the open-loop error divided by 1 + Kp ([3.3]), and the
  // measured ratio beside the thesis's.
  Json ratios = Json::array();
  for (const SchemeRun& r : runs) {
    if (open_loop == nullptr || r.scheme.controller != "impedance" || r.scheme.id == "open-loop" || r.rms <= 0.0)
      continue;
    const double kp = r.scheme.force_gain;
    std::vector<double> predicted;
    for (double e : open_loop->error) predicted.push_back(e / (1.0 + kp));
    result.set("predicted", Json::object()
                                .set("label", fmt::format("open loop / (1 + {:g}): predicted", kp))
                                .set("time_s", open_loop->time)
                                .set("force_error_n", predicted));
    const double ratio = open_loop->rms / r.rms;
    ratios.push(Json::object()
                    .set("what", fmt::format("RMS error, open loop / {}", r.scheme.label))
                    .set("ours", ratio)
                    .set("predicted", 1.0 + kp)
                    .set("published", kp == 1.5 ? Json(2.5) : Json()));
    fmt::print("open loop / {}: {:.2f} (model: 1 + Kp = {:.2f}{})\n", r.scheme.label, ratio, 1.0 + kp,
               kp == 1.5 ? "; thesis: about 2.5" : "");
  }
  result.set("ratios", ratios).set("example_session", example_yaml);
  publish_result(o.common.report(), "backdrivability", result);
  return 0;  // an unstable scheme is a result of the experiment, not an error
}

}  // namespace

void add_backdrivability_command(CLI::App& app, int& exit_code) {
  auto o = command_options<Options>();
  CLI::App* cmd = app.add_subcommand(
      "backdrivability",
      "A stiff guide moves the handle along x (constant-acceleration and constant-velocity phases); the force "
      "error of each scheme, and the model's prediction for force feedback");
  add_common_options(cmd, o->common);
  add_scheme_options(cmd, o->schemes, o->virtual_mass_kg);
  cmd->add_option("--distance", o->distance_m, "length of the guide's stroke [m]")
      ->check(CLI::Range(0.01, 0.4))
      ->capture_default_str();
  cmd->add_option("--acceleration", o->acceleration_m_s2, "the guide's acceleration [m/s^2]")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--speed", o->speed_m_s, "the guide's cruise speed [m/s]")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--legs", o->legs, "strokes (out, back, ...)")->check(CLI::Range(1, 100))->capture_default_str();
  cmd->callback([o, &exit_code] {
    Options run_options = *o;
    if (run_options.common.quick) run_options.legs = std::min(run_options.legs, 2);
    exit_code = run(run_options);
  });
}

}  // namespace hapticd::eval
