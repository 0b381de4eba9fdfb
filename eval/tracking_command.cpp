#include "tracking_command.hpp"

#include <fmt/format.h>

#include <cmath>

#include "eval_options.hpp"
#include "experiment/device_model.hpp"
#include "experiment/rig.hpp"
#include "report/progress.hpp"

namespace hapticd::eval {
namespace {

struct Options {
  CommonOptions common;
  std::vector<std::string> schemes{"rac:10000:ff", "rac:10000",    "ijc:10000:ff",
                                   "ijc:10000",    "tjc:10000:ff", "tjc:10000"};
  // The path: along x at constant y and z, from `start` out by `distance` and back, +-acceleration phases.
  std::vector<double> start{-0.15, 0.16, 0.0};  // the folded elbow: J's condition number up to 5.9
  double distance_m = 0.3, acceleration_m_s2 = 10.0, speed_m_s = 0.5;  // 1 m/s overspeeds the joints there
  int legs = 2;
};

constexpr double kRate = 2000.0;
constexpr double kPathStart = 0.3;
constexpr int kPlotDecimation = 4;

struct SchemeRun {
  Scheme scheme;
  std::vector<double> time, along, across, error_x;
  double rms_mm = 0.0, peak_mm = 0.0;
  std::string fault;
};

int run(const Options& o) {
  DeviceModel device(o.common.device);
  const Eigen::Vector3d start(o.start[0], o.start[1], o.start[2]);
  const std::vector<double> q0 = device.joints_at(start);
  // How near the path comes to a singularity: the condition number of the translational Jacobian along it.
  double worst_condition = 0.0, worst_at = 0.0;
  for (int i = 0; i <= 30; ++i) {
    const double s = o.distance_m * i / 30.0;
    const auto q = device.joints_at(start + Eigen::Vector3d(s, 0, 0));
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(device.inertia_at(q).jacobian);
    const double c = svd.singularValues()(0) / svd.singularValues()(svd.singularValues().size() - 1);
    if (c > worst_condition) {
      worst_condition = c;
      worst_at = start.x() + s;
    }
  }
  std::vector<Scheme> schemes;
  for (const std::string& text : o.schemes) {
    schemes.push_back(parse_scheme(text, 1.0));
    if (schemes.back().display != Scheme::Display::admittance)
      throw std::invalid_argument("tracking: '" + text + "' is not an admittance scheme (rac, ijc, tjc)");
  }
  const double v = std::min(o.speed_m_s, std::sqrt(o.acceleration_m_s2 * o.distance_m));  // the cruise speed
  const double leg_s = shuttle_leg_s(o.distance_m, o.acceleration_m_s2, o.speed_m_s);
  const auto cycles = static_cast<std::uint64_t>(std::ceil((kPathStart + o.legs * leg_s + 0.2) * kRate));
  Progress progress("tracking", schemes.size());
  std::vector<SchemeRun> runs;
  std::string example_yaml;
  for (const Scheme& scheme : schemes) {
    RigSpec spec;
    spec.device = rig_device(o.common);
    spec.device.initial_position = q0;
    spec.scheme = scheme;
    spec.seed = o.common.seed;
    spec.model_plugin = "trajectory";
    spec.model = {"path: shuttle", fmt::format("path_m: [{:.17g}, 0, 0]", o.distance_m),
                  fmt::format("path_start_s: {}", kPathStart),
                  fmt::format("path_acceleration_m_s2: {:.17g}", o.acceleration_m_s2),
                  fmt::format("path_speed_m_s: {:.17g}", o.speed_m_s)};
    if (example_yaml.empty()) example_yaml = rig_yaml(spec);
    server::Session session = make_rig_session(spec);
    SchemeRun r{scheme, {}, {}, {}, {}, 0.0, 0.0, {}};
    double sum = 0.0;
    std::size_t n = 0, k = 0;
    r.fault = run_rig(session, cycles, [&](const RigSample& s) {
      const Eigen::Vector3d e = s.position - s.desired_position;
      if (s.t >= kPathStart && s.t <= kPathStart + o.legs * leg_s) {
        sum += e.squaredNorm();
        r.peak_mm = std::max(r.peak_mm, 1e3 * e.norm());
        ++n;
      }
      if (k++ % kPlotDecimation == 0) {
        r.time.push_back(s.t);
        r.along.push_back(s.desired_position.x() - start.x());
        r.error_x.push_back(1e3 * e.x());
        r.across.push_back(1e3 * e.tail<2>().norm());
      }
    });
    r.rms_mm = n > 0 ? 1e3 * std::sqrt(sum / static_cast<double>(n)) : 0.0;
    runs.push_back(std::move(r));
    progress.advance(scheme.loop_id);
  }
  fmt::print(
      "path along x from ({:.2f}, {:.2f}, {:.2f}) m, {:.2f} m, +-{:g} m/s^2, {:g} m/s; condition number of J up "
      "to {:.1f} (at x = {:.2f} m)\n",
      start.x(), start.y(), start.z(), o.distance_m, o.acceleration_m_s2, v, worst_condition, worst_at);
  fmt::print("{:<32} {:>12} {:>12}\n", "inner loop", "RMS error", "peak error");
  Json list = Json::array();
  for (const SchemeRun& r : runs) {
    fmt::print("{:<32} {:>9.3f} mm {:>9.3f} mm{}\n", r.scheme.loop_label, r.rms_mm, r.peak_mm,
               r.fault.empty() ? "" : "   FAULT: " + r.fault);
    list.push(Json::object()
                  .set("id", r.scheme.loop_id)
                  .set("label", r.scheme.loop_label)
                  .set("rms_error_mm", r.rms_mm)
                  .set("peak_error_mm", r.peak_mm)
                  .set("fault", r.fault)
                  .set("time_s", r.time)
                  .set("path_m", r.along)
                  .set("error_x_mm", r.error_x)
                  .set("error_across_mm", r.across));
  }
  Json result = Json::object();
  result.set("experiment", "tracking")
      .set("title", "Tracking of a fast path near a singular region (appendix B)")
      .set("device", o.common.device)
      .set("path", Json::object()
                       .set("start_m", o.start)
                       .set("distance_m", o.distance_m)
                       .set("acceleration_m_s2", o.acceleration_m_s2)
                       .set("speed_m_s", v)
                       .set("legs", o.legs)
                       .set("worst_condition", worst_condition)
                       .set("worst_condition_at_x_m", worst_at))
      .set("schemes", list)
      .set("command", command_line())
      .set("example_session", example_yaml);
  publish_result(o.common.report(), "tracking", result);
  return 0;
}

}  // namespace

void add_tracking_command(CLI::App& app, int& exit_code) {
  auto o = command_options<Options>();
  CLI::App* cmd = app.add_subcommand(
      "tracking",
      "The trajectory model plays a fast path along x (+-10 m/s^2) near a singular region; the tracking error of "
      "each inner loop with and without acceleration feedforward (appendix B)");
  add_common_options(cmd, o->common);
  cmd->add_option("--schemes", o->schemes, "inner loops: rac:KP[:ff], ijc:KP[:ff], tjc:KP[:ff]")->capture_default_str();
  cmd->add_option("--start", o->start, "where the path starts (world, m)")->expected(3)->capture_default_str();
  cmd->add_option("--distance", o->distance_m, "length of the path [m]")
      ->check(CLI::Range(0.01, 0.6))
      ->capture_default_str();
  cmd->add_option("--acceleration", o->acceleration_m_s2, "acceleration of its phases [m/s^2]")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--speed", o->speed_m_s, "its cruise speed [m/s]")->check(CLI::PositiveNumber)->capture_default_str();
  cmd->add_option("--legs", o->legs, "strokes (out, back, ...)")->check(CLI::Range(1, 20))->capture_default_str();
  cmd->callback([o, &exit_code] {
    Options run_options = *o;
    if (run_options.common.quick) {
      run_options.schemes = {"rac:10000:ff", "tjc:10000"};
      run_options.legs = 1;
    }
    exit_code = run(run_options);
  });
}

}  // namespace hapticd::eval
