#include "friction_command.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include "device_presets.hpp"
#include "eval_options.hpp"
#include "experiment/rig.hpp"
#include "hapticd/model/friction_file.hpp"
#include "report/progress.hpp"

namespace hapticd::eval {
namespace {

struct Options {
  CommonOptions common;
  std::vector<double> joints;  // empty: all
  std::vector<double> speeds;  // empty, 0: the device's (with_device_defaults)
  double acceleration = 0.0;
  double duration_s = 0.0;
};

// The strokes each device takes. ViSHaRD3's joints up to 2 rad/s at 30 rad/s^2 (its shipped identification
// session). ViSHaRD6 and ViSHaRD10 swing a long arm on their first joints: the strokes stop at 0.8 rad/s (the
// handle then stays under the safety's 1 m/s, where its damping would join the measurement, and 1.5 m/s, where it
// faults) and turn gently - 5 rad/s^2 on ViSHaRD6, 2 on ViSHaRD10 (at 5 the reaction of joint 1's turn saturates
// the hold of joints 2-4 and the arm whips into a joint overspeed). The durations are what the identification
// needs for every joint at these strokes; `--quick` identifies joint 1 alone at five speeds.
struct DeviceStrokes {
  std::vector<double> speeds;
  double acceleration, duration_s;
};

DeviceStrokes device_strokes(const std::string& device, bool quick) {
  const double acceleration = device == "vishard6" ? 5.0 : device == "vishard10" ? 2.0 : 30.0;
  if (device == "vishard3")
    return quick ? DeviceStrokes{{0.1, 0.3, 0.6, 1.2, 2.0}, acceleration, 30.0}
                 : DeviceStrokes{
                       {0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.6, 0.8, 1, 1.2, 1.4, 1.6, 1.8, 2}, acceleration, 186.0};
  if (quick) return {{0.1, 0.2, 0.4, 0.6, 0.8}, acceleration, 40.0};
  return {{0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.6, 0.8}, acceleration, device == "vishard6" ? 350.0 : 600.0};
}

Options with_device_defaults(Options o) {
  const DeviceStrokes d = device_strokes(o.common.device, o.common.quick);
  if (o.common.quick) o.joints = {1};
  if (o.speeds.empty() || o.common.quick) o.speeds = d.speeds;
  if (o.acceleration <= 0.0) o.acceleration = d.acceleration;
  if (o.duration_s <= 0.0 || o.common.quick) o.duration_s = d.duration_s;
  return o;
}

constexpr double kRate = 2000.0;
constexpr double kBinWidth = 0.05;  // rad/s
constexpr double kMaxSpeed = 2.2;

// The simulator's friction as it acted: the true friction torque of each joint (on the motor side, where the
// simulation applies it) averaged per bin of the motor velocity over the cruise phases; the samples near rest
// (stiction) left out.
struct TruthCurve {
  std::vector<double> sum, count;
  TruthCurve() : sum(2 * static_cast<std::size_t>(kMaxSpeed / kBinWidth)), count(sum.size()) {}
  void add(double velocity, double torque) {
    const auto bin = static_cast<long>(std::floor((velocity + kMaxSpeed) / kBinWidth));
    if (bin < 0 || bin >= static_cast<long>(sum.size())) return;
    sum[static_cast<std::size_t>(bin)] += torque;
    count[static_cast<std::size_t>(bin)] += 1.0;
  }
};

int run(const Options& o) {
  namespace fs = std::filesystem;
  fs::create_directories(o.common.out);
  const fs::path output = fs::absolute(fs::path(o.common.out) / "friction-identified.yaml");
  RigSpec spec;
  spec.device.name = o.common.device;
  spec.device.sim_parameters = {"warm_up: false"};  // identify at one temperature (the 26 C curve)
  spec.device.sim_parameters.insert(spec.device.sim_parameters.end(), o.common.sim_parameters.begin(),
                                    o.common.sim_parameters.end());
  spec.attachment = {"attachment: none"};
  spec.device.initial_position = device_preset(o.common.device).identification_position;  // empty: the rig's
  spec.seed = o.common.seed;
  std::vector<long> joint_numbers;
  for (double j : o.joints) joint_numbers.push_back(std::lround(j));
  spec.scheme = {"friction-identification",
                 "friction identification",
                 Scheme::Display::impedance,
                 "friction_identification",
                 fmt::format("output_file: '{}', joints: [{}], speeds: [{}], acceleration: {}", output.string(),
                             fmt::join(joint_numbers, ", "), fmt::join(o.speeds, ", "), o.acceleration),
                 0.0,
                 0.0,
                 "friction-identification",
                 "friction identification",
                 false,
                 false};
  const std::string yaml = rig_yaml(spec);
  std::string fault;
  std::vector<TruthCurve> truth;
  {
    server::Session session = make_rig_session(spec);
    const auto cycles = static_cast<std::uint64_t>(std::llround(o.duration_s * kRate));
    Progress progress("friction", 20);
    for (std::uint64_t k = 0; k < cycles && fault.empty(); ++k) {
      session.step(1);
      const server::DeviceView v = session.device("dut");
      fault = v.fault;
      if (!v.truth) continue;
      const auto n = static_cast<std::size_t>(v.truth->motor_velocity.size());
      truth.resize(n);
      for (std::size_t j = 0; j < n; ++j) {
        const double w = v.truth->motor_velocity[static_cast<Eigen::Index>(j)];
        const double friction = v.truth->friction_torque[static_cast<Eigen::Index>(j)];
        // Cruising: the drive's torque goes to friction (within 0.3 N m), not into accelerating or loading the
        // joint (the load-dependent part would otherwise join the curve).
        const double rest =
            std::abs(std::abs(v.truth->motor_torque[static_cast<Eigen::Index>(j)]) - std::abs(friction));
        if (std::abs(w) > 0.02 && rest < 0.3) truth[j].add(w, friction);
      }
      if ((k + 1) % (cycles / 20) == 0) progress.advance(fmt::format("{:.0f} s", v.time_s));
    }
    if (!fault.empty()) throw std::runtime_error("the identification run faulted: " + fault);
    session.stop();  // the identification writes its file as it is deactivated
  }
  const model::FrictionFile identified = model::read_friction_file(output);
  Json joints = Json::array();
  fmt::print("{:<8} {:>10} {:>12} {:>22}\n", "joint", "coulomb", "break-away", "sliding error vs truth");
  for (std::size_t j = 0; j < identified.joints.size() && j < truth.size(); ++j) {
    const model::FrictionModel& m = identified.joints[j];
    if (m.p[0] == 0.0) continue;  // not identified (not selected)
    std::vector<double> velocity, true_torque, identified_torque;
    double worst = 0.0, sum = 0.0;
    for (std::size_t b = 0; b < truth[j].sum.size(); ++b) {
      if (truth[j].count[b] < 20.0) continue;
      const double v = -kMaxSpeed + (static_cast<double>(b) + 0.5) * kBinWidth;
      const double t = truth[j].sum[b] / truth[j].count[b];
      const double fit = std::copysign(m.sliding(std::abs(v)), v);
      velocity.push_back(v);
      true_torque.push_back(t);
      identified_torque.push_back(fit);
      const double error = std::abs(fit - t) / std::max(std::abs(t), 1e-3);
      worst = std::max(worst, error);
      sum += error * error;
    }
    // No bin to compare (the joint carried a load through every cruise, so the truth there is not sliding
    // friction alone): no error, null in the JSON, said so - not 0 %.
    double rms = std::numeric_limits<double>::quiet_NaN();
    if (!velocity.empty()) {
      rms = std::sqrt(sum / static_cast<double>(velocity.size()));
      fmt::print("{:<8} {:>8.3f} Nm {:>9.3f} Nm {:>9.1f} % RMS, {:.1f} % worst\n", identified.joint_names[j], m.p[0],
                 m.breakaway_nm, 100 * rms, 100 * worst);
    } else {
      worst = std::numeric_limits<double>::quiet_NaN();
      fmt::print("{:<8} {:>8.3f} Nm {:>9.3f} Nm   not compared: no cruise without load\n", identified.joint_names[j],
                 m.p[0], m.breakaway_nm);
    }
    joints.push(Json::object()
                    .set("joint", identified.joint_names[j])
                    .set("coulomb_nm", m.p[0])
                    .set("breakaway_nm", m.breakaway_nm)
                    .set("rms_error_percent", 100 * rms)
                    .set("worst_error_percent", 100 * worst)
                    .set("velocity_rad_s", velocity)
                    .set("true_torque_nm", true_torque)
                    .set("identified_torque_nm", identified_torque));
  }
  Json result = Json::object();
  result.set("experiment", "friction")
      .set("title", "Friction identification against the simulator's truth")
      .set("device", o.common.device)
      .set("friction_file", output.string())
      .set("joints", joints)
      .set("command", command_line())
      .set("example_session", yaml);
  publish_result(o.common.report(), "friction", result);
  return 0;
}

}  // namespace

void add_friction_command(CLI::App& app, int& exit_code) {
  auto o = command_options<Options>();
  CLI::App* cmd = app.add_subcommand(
      "friction",
      "Runs the friction identification on the simulated device and plots the identified curves against the "
      "friction the simulation applied");
  add_common_options(cmd, o->common, {"vishard3", "vishard6", "vishard10"});
  cmd->add_option("--joints", o->joints, "joints to identify, counted from 1 (default: all)");
  cmd->add_option("--speeds", o->speeds,
                  "cruise speeds of the strokes [rad/s] (default: 0.05 .. 2 on vishard3, 0.05 .. 0.8 on vishard6 and "
                  "vishard10)");
  cmd->add_option("--acceleration", o->acceleration,
                  "acceleration at the ends of each stroke [rad/s^2] (default: 30 on vishard3, 5 on vishard6, 2 on "
                  "vishard10)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--duration", o->duration_s,
                  "simulated time the identification is given [s] (default: what it needs for every joint: 186 s on "
                  "vishard3, 350 s on vishard6, 600 s on vishard10)")
      ->check(CLI::Range(1.0, 3600.0));
  cmd->callback([o, &exit_code] { exit_code = run(with_device_defaults(*o)); });
}

}  // namespace hapticd::eval
