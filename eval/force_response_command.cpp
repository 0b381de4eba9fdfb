#include "force_response_command.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "analysis/frequency_response.hpp"
#include "eval_options.hpp"
#include "experiment/rig.hpp"
#include "report/progress.hpp"

namespace hapticd::eval {
namespace {

struct Options {
  CommonOptions common;
  std::vector<std::string> schemes{"open-loop", "pd:2.5:0.003", "rac:10000:ff", "rac:1000:ff"};
  int frequencies = 60;
  double from_hz = 1.0, to_hz = 60.0;
  double amplitude_n = 5.0, open_loop_amplitude_n = 10.0;
  double virtual_mass_kg = 3.0;
  std::string axis = "z";
};

constexpr double kRate = 2000.0;
constexpr double kScriptStart = 0.5;  // the device settles (and the soft start ends) before the sine begins

// The thesis's figures for the schemes it measured (CONTROL-METHODS.md section 4; issue 20's table).
Json published(const Scheme& s) {
  Json p = Json::object();
  if (s.id == "rac-kp10000-m3-ff") p.set("resonance_hz", 21.0).set("bandwidth_hz", 26.0);
  if (s.id == "rac-kp1000-m3-ff") p.set("resonance_hz", 24.0).set("bandwidth_hz", 28.5);
  if (s.id == "open-loop") p.set("bandwidth_hz", 33.0);
  if (s.id == "pd-kp2.5-kd0.003") p.set("bandwidth_hz", "above 60");
  return p;
}

struct Window {
  double transient_s, measure_s;
};
Window window_for(double f, bool quick) {
  const double periods = quick ? 2.0 : 3.0;
  const double measure = std::ceil(std::max(quick ? 0.2 : 0.5, periods / f) * f) / f;  // whole periods
  return {std::max(quick ? 0.2 : 0.3, 2.0 / f), measure};
}

int run(const Options& o) {
  const int axis = o.axis == "x" ? 0 : o.axis == "y" ? 1 : 2;
  std::vector<double> freqs;
  const int n = o.common.quick ? std::min(o.frequencies, 6) : o.frequencies;
  for (int i = 0; i < n; ++i) freqs.push_back(n == 1 ? o.from_hz : o.from_hz + (o.to_hz - o.from_hz) * i / (n - 1));
  std::vector<Scheme> schemes;
  for (const std::string& text : o.schemes) schemes.push_back(parse_scheme(text, o.virtual_mass_kg));

  Json result = Json::object();
  result.set("experiment", "force-response")
      .set("title", "Dynamic force precision (isometric)")
      .set("device", o.common.device)
      .set("axis", o.axis)
      .set("virtual_mass_kg", o.virtual_mass_kg)
      .set("quick", o.common.quick)
      .set("command", command_line());
  Json scheme_results = Json::array();
  Progress progress("force-response", schemes.size() * freqs.size());
  fmt::print("{:<36} {:>10} {:>10} {:>10} {:>12}   published\n", "scheme", "bandwidth", "resonance", "peak gain",
             "D_rms(1st)");
  std::string example_yaml;
  for (const Scheme& scheme : schemes) {
    const double amplitude = scheme.id == "open-loop" ? o.open_loop_amplitude_n : o.amplitude_n;
    std::vector<FrequencyPoint> points;
    Json faults = Json::array();
    for (double f : freqs) {
      RigSpec spec;
      spec.device = rig_device(o.common);
      spec.scheme = scheme;
      spec.seed = o.common.seed;
      Eigen::Vector3d force = Eigen::Vector3d::Zero();
      force[axis] = amplitude;
      spec.script = {"signal: sine", fmt::format("force_n: [{}, {}, {}]", force.x(), force.y(), force.z()),
                     fmt::format("frequency_hz: {:.17g}", f), fmt::format("start_s: {}", kScriptStart)};
      spec.attachment = {"attachment: position_source"};
      if (example_yaml.empty()) example_yaml = rig_yaml(spec);
      server::Session session = make_rig_session(spec);
      const Window w = window_for(f, o.common.quick);
      const double begin = kScriptStart + w.transient_s;
      const auto cycles = static_cast<std::uint64_t>(std::ceil((begin + w.measure_s) * kRate)) + 2;
      std::vector<double> t, in, out;
      const std::string fault = run_rig(session, cycles, [&](const RigSample& s) {
        if (s.t < begin || s.t >= begin + w.measure_s) return;
        t.push_back(s.t);
        in.push_back(s.commanded_force[axis]);
        out.push_back(s.measured_force[axis]);
      });
      progress.advance(fmt::format("{}: {:.1f} Hz", scheme.id, f));
      if (!fault.empty()) {
        faults.push(Json::object().set("frequency_hz", f).set("fault", fault));
        continue;
      }
      points.push_back(response_at(t, in, out, f));
    }
    Json series = Json::object();
    std::vector<double> fs, gain, phase, distortion;
    for (const FrequencyPoint& p : points) {
      fs.push_back(p.frequency_hz);
      gain.push_back(p.gain);
      phase.push_back(p.phase_rad * 180.0 / std::numbers::pi);
      distortion.push_back(p.distortion_percent);
    }
    // NaN when there is none (written as null).
    const double none = std::numeric_limits<double>::quiet_NaN();
    const double bandwidth = points.empty() ? none : bandwidth_3db(points).value_or(none);
    const double resonance = points.empty() ? none : resonance_hz(points).value_or(none);
    double peak = 0.0;
    for (double g : gain) peak = std::max(peak, g);
    const Json thesis = published(scheme);
    Json r = Json::object();
    r.set("id", scheme.id)
        .set("label", scheme.label)
        .set("amplitude_n", amplitude)
        .set("frequency_hz", fs)
        .set("gain", gain)
        .set("phase_deg", phase)
        .set("distortion_percent", distortion)
        .set("bandwidth_hz", bandwidth)
        .set("bandwidth_above_range", points.size() == freqs.size() && std::isnan(bandwidth))
        .set("resonance_hz", resonance)
        .set("peak_gain", peak)
        .set("faults", faults)
        .set("published", thesis);
    scheme_results.push(r);
    const std::string bandwidth_text = !std::isnan(bandwidth)          ? fmt::format("{:.1f} Hz", bandwidth)
                                       : points.size() == freqs.size() ? fmt::format("> {:g} Hz", freqs.back())
                                                                       : std::string("-");
    const std::string resonance_text = !std::isnan(resonance) ? fmt::format("{:.1f} Hz", resonance) : "-";
    fmt::print("{:<36} {:>10} {:>10} {:>10.2f} {:>11.1f}%   {}\n", scheme.label, bandwidth_text, resonance_text, peak,
               distortion.empty() ? 0.0 : distortion.front(), thesis.empty() ? "" : thesis.dump());
    if (!faults.empty()) fmt::print("  {} unstable: {}\n", scheme.id, faults.dump());
  }
  result.set("schemes", scheme_results).set("example_session", example_yaml);
  publish_result(o.common.report(), "force-response", result);
  return 0;  // an unstable scheme is a result of the experiment, not an error
}

}  // namespace

void add_force_response_command(CLI::App& app, int& exit_code) {
  auto o = command_options<Options>();
  CLI::App* cmd = app.add_subcommand(
      "force-response",
      "Dynamic force precision: the handle held by a stiff guide, sinusoidal desired force, gain, phase, "
      "distortion and -3 dB bandwidth per scheme");
  add_common_options(cmd, o->common);
  add_scheme_options(cmd, o->schemes, o->virtual_mass_kg);
  cmd->add_option("--frequencies", o->frequencies, "number of frequencies (evenly spaced)")
      ->check(CLI::Range(1, 500))
      ->capture_default_str();
  cmd->add_option("--from", o->from_hz, "lowest frequency [Hz]")->check(CLI::PositiveNumber)->capture_default_str();
  cmd->add_option("--to", o->to_hz, "highest frequency [Hz]")->check(CLI::PositiveNumber)->capture_default_str();
  cmd->add_option("--amplitude", o->amplitude_n, "desired force amplitude [N]")->capture_default_str();
  cmd->add_option("--open-loop-amplitude", o->open_loop_amplitude_n, "the same for open-loop impedance control [N]")
      ->capture_default_str();
  cmd->add_option("--axis", o->axis, "direction of the force (world)")
      ->check(CLI::IsMember({"x", "y", "z"}))
      ->capture_default_str();
  cmd->callback([o, &exit_code] { exit_code = run(*o); });
}

}  // namespace hapticd::eval
