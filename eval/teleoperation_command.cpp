#include "teleoperation_command.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>

#include "device_presets.hpp"
#include "eval_options.hpp"
#include "experiment/teleop_trial.hpp"
#include "report/progress.hpp"

namespace hapticd::eval {
namespace {

struct Options {
  CommonOptions common;
  std::vector<double> round_trips_ms{0.0, 10.0, 50.0, 200.0, 500.0};
  std::vector<double> losses_percent{0.0, 5.0, 20.0};
  std::vector<std::string> schemes{"none", "tdpa"};
  std::vector<std::string> tasks{"wall", "free"};
  std::string architecture = "position_force";
  double jitter_ms = 0.0;
  double duration_s = 6.0;
  double stiffness = -1.0;  // < 0: the pair's (pair_link below)
  double damping = -1.0;
  double motion_scale = 1.0;
  double force_scale = 1.0;
  int dof = 3;  // 6: the ViSHaRD6 pair in six degrees of freedom (master6.yaml, remote6.yaml)
  // The wall's run over time at this delay (and the lowest loss run) goes into the report; < 0: the round trip
  // run nearest to 200 ms.
  double trace_round_trip_ms = -1.0;
  std::string table;  // also the rows alone, to this file (the docs' tables)
};

teleop::Passivity parse_passivity(const std::string& s) {
  if (s == "none") return teleop::Passivity::none;
  if (s == "wave") return teleop::Passivity::wave;
  return teleop::Passivity::tdpa;
}

std::string cell(const TeleopResult& r) {
  if (!r.fault.empty()) return "fault";
  return fmt::format("{}{}", r.passive ? "P" : "-", r.stable ? "S" : "-");
}

int run(const Options& o) {
  std::string tried;
  if (o.dof == 6 && std::find(o.schemes.begin(), o.schemes.end(), "wave") != o.schemes.end())
    throw std::invalid_argument("--dof 6: wave variables carry translation only (--passivity none tdpa)");
  const auto master_file = find_config_file("sessions/teleoperation/master.yaml", &tried);
  if (!master_file) throw std::runtime_error("no config/sessions/teleoperation/master.yaml; looked at:" + tried);
  const std::filesystem::path config_dir = master_file->parent_path();

  std::vector<TeleopTask> tasks;
  for (const std::string& t : o.tasks) tasks.push_back(t == "free" ? TeleopTask::free : TeleopTask::wall);
  // The wall's run over time is kept at the trace's round trip and the lowest loss asked for (none, when 0 is in
  // the list); a trace round trip the grid does not have is an error, not a report without its figure.
  double trace_rtt = o.trace_round_trip_ms;
  if (trace_rtt < 0.0) {
    trace_rtt = o.round_trips_ms.front();
    for (const double r : o.round_trips_ms)
      if (std::abs(r - 200.0) < std::abs(trace_rtt - 200.0)) trace_rtt = r;
  } else if (std::find(o.round_trips_ms.begin(), o.round_trips_ms.end(), trace_rtt) == o.round_trips_ms.end()) {
    throw std::invalid_argument(
        fmt::format("--trace-round-trip {:g} is not one of the round trips run ({}): choose "
                    "one of them, or add it to --round-trips",
                    trace_rtt, fmt::join(o.round_trips_ms, ", ")));
  }
  const double trace_loss = *std::min_element(o.losses_percent.begin(), o.losses_percent.end());
  fmt::print("the report's figure: the wall at {:g} ms round trip and {:g} % loss\n", trace_rtt, trace_loss);
  Progress progress("teleoperation",
                    tasks.size() * o.schemes.size() * o.round_trips_ms.size() * o.losses_percent.size());
  Json rows = Json::array();
  double largest_delay_error = 0.0;
  Json traces = Json::array();
  fmt::print(
      "teleoperation, {}: P passive, S stable; the wall's felt stiffness K [N/m], free motion's drift [mm]; "
      "lowest energy E [mJ]\n",
      o.architecture);
  for (const TeleopTask task : tasks) {
    for (const std::string& scheme : o.schemes) {
      fmt::print("{} / {}\n", to_string(task), scheme);
      for (const double rtt : o.round_trips_ms) {
        fmt::print("  {:>5g} ms:", rtt);
        for (const double loss : o.losses_percent) {
          TeleopRow row;
          row.task = task;
          row.round_trip_s = rtt * 1e-3;
          row.loss = loss * 1e-2;
          row.jitter_s = o.jitter_ms * 1e-3;
          row.duration_s = o.duration_s;
          row.seed = o.common.seed;
          row.link = pair_link(o.dof == 6);
          row.six_dof = o.dof == 6;
          row.link.architecture = o.architecture == "position_position" ? teleop::Architecture::position_position
                                                                        : teleop::Architecture::position_force;
          row.link.passivity = parse_passivity(scheme);
          if (o.stiffness >= 0.0) row.link.stiffness = o.stiffness;
          if (o.damping >= 0.0) row.link.damping = o.damping;
          row.link.motion_scale = o.motion_scale;
          row.link.force_scale = o.force_scale;
          // The wall at the trace delay and the lowest loss: its run over time, for the report's figure.
          row.keep_samples = task == TeleopTask::wall && rtt == trace_rtt && loss == trace_loss;
          const TeleopResult r = run_teleop_trial(row, config_dir);
          if (row.keep_samples) {
            std::vector<double> t, xm, xr, f, am, ar, tm;
            for (std::size_t k = 0; k < r.samples.size(); k += 10) {  // 100 Hz
              t.push_back(r.samples[k].t);
              xm.push_back(r.samples[k].master.x());
              xr.push_back(r.samples[k].remote.x());
              f.push_back(r.samples[k].master_force.x());
              am.push_back(r.samples[k].master_angle);
              ar.push_back(r.samples[k].remote_angle);
              tm.push_back(r.samples[k].master_torque);
            }
            Json trace = Json::object()
                             .set("passivity", scheme)
                             .set("round_trip_ms", rtt)
                             .set("loss_percent", loss)
                             .set("time_s", t)
                             .set("master_x_m", xm)
                             .set("remote_x_m", xr)
                             .set("master_force_x_n", f);
            if (row.six_dof)
              trace.set("master_angle_z_rad", am).set("remote_angle_z_rad", ar).set("master_torque_z_n_m", tm);
            traces.push(trace);
          }
          progress.advance(fmt::format("{} {} {:g} ms {:g} %", to_string(task), scheme, rtt, loss));
          fmt::print("  {:>2g}%: {:<5} {} E {:>9.1f}", loss, cell(r),
                     task == TeleopTask::wall
                         ? (std::isnan(r.felt_stiffness_n_per_m) ? std::string("K     -")
                                                                 : fmt::format("K {:>5.0f}", r.felt_stiffness_n_per_m))
                         : fmt::format("drift {:>5.1f}", r.drift_mm),
                     1e3 * r.min_energy_j);
          if (row.six_dof)
            fmt::print(" {}", task == TeleopTask::wall
                                  ? fmt::format("Kr {:.2f}", r.felt_rotational_stiffness_n_m_per_rad)
                                  : fmt::format("turn {:.2f}", r.rotation_oscillation));
          Json entry =
              Json::object()
                  .set("task", to_string(task))
                  .set("passivity", scheme)
                  .set("round_trip_ms", rtt)
                  .set("loss_percent", loss)
                  .set("passive", r.passive)
                  .set("stable", r.stable)
                  .set("fault", r.fault)
                  .set("min_energy_j", r.min_energy_j)
                  .set("oscillation", r.oscillation_mm)
                  .set("felt_stiffness_n_per_m", r.felt_stiffness_n_per_m)
                  .set("drift_mm", r.drift_mm)
                  .set("max_force_n", r.max_force_n)
                  .set("dissipated_j", r.dissipated_j)
                  .set("packets_lost", static_cast<unsigned long>(r.to_remote.lost + r.to_master.lost))
                  .set("delay_true_ms",
                       Json::array().push(1e3 * r.delays.true_to_remote_s).push(1e3 * r.delays.true_to_master_s))
                  .set("delay_measured_master_ms", Json::array()
                                                       .push(1e3 * r.delays.master.mean_delay_out_s)
                                                       .push(1e3 * r.delays.master.mean_delay_in_s))
                  .set("delay_measured_remote_ms", Json::array()
                                                       .push(1e3 * r.delays.remote.mean_delay_in_s)
                                                       .push(1e3 * r.delays.remote.mean_delay_out_s))
                  .set("clock_offset_s", Json::array().push(r.delays.true_offset_s).push(r.delays.master.offset_s));
          if (row.six_dof)
            entry.set("felt_rotational_stiffness_n_m_per_rad", r.felt_rotational_stiffness_n_m_per_rad)
                .set("rotation_oscillation", r.rotation_oscillation)
                .set("max_torque_n_m", r.max_torque_n_m);
          rows.push(entry);
          largest_delay_error = std::max(largest_delay_error, r.delays.largest_error_s);
        }
        fmt::print("\n");
      }
    }
  }
  fmt::print(
      "one-way delays as both sides measured them from the packets' times (the remote's clock {:g} s ahead, {:g} ppm "
      "fast): within {:.3f} ms of the channel's true means in every row\n",
      TeleopRow{}.remote_clock_offset_s, TeleopRow{}.remote_clock_drift_ppm, 1e3 * largest_delay_error);
  Json result = Json::object();
  result.set("experiment", "teleoperation")
      .set("title", "Teleoperation: a stiff wall and free motion through a delayed, lossy link")
      .set("device", o.common.device)
      .set("architecture", o.architecture)
      .set("stiffness_n_per_m", o.stiffness >= 0.0 ? o.stiffness : pair_link(o.dof == 6).stiffness)
      .set("damping_n_s_per_m", o.damping >= 0.0 ? o.damping : pair_link(o.dof == 6).damping)
      .set("jitter_ms", o.jitter_ms)
      .set("duration_s", o.duration_s)
      .set("wall_offset_m", 0.03)
      .set("dof", o.dof)
      .set("largest_delay_error_ms", 1e3 * largest_delay_error)
      .set("rows", rows)
      .set("traces", traces)
      .set("command", command_line());
  publish_result(o.common.report(), "teleoperation", result);
  if (!o.table.empty()) {
    std::ofstream out(o.table);
    out << rows.dump(1) << "\n";
    if (!out) throw std::runtime_error("cannot write " + o.table);
    fmt::print("rows: {}\n", o.table);
  }
  return 0;
}

}  // namespace

void add_teleoperation_command(CLI::App& app, int& exit_code) {
  auto o = command_options<Options>();
  CLI::App* cmd = app.add_subcommand(
      "teleoperation",
      "Bilateral teleoperation of a simulated ViSHaRD3 by another: a stiff wall and free motion at each round-trip "
      "delay and loss, with and without passivity control (passive, stable, felt stiffness, drift)");
  add_common_options(cmd, o->common);
  cmd->add_option("--round-trips", o->round_trips_ms, "round-trip delays [ms]")
      ->check(CLI::Range(0.0, 5000.0))
      ->capture_default_str();
  cmd->add_option("--losses", o->losses_percent, "packet losses each way [%]")
      ->check(CLI::Range(0.0, 99.0))
      ->capture_default_str();
  cmd->add_option("--passivity", o->schemes, "none, tdpa, wave")
      ->check(CLI::IsMember({"none", "tdpa", "wave"}))
      ->capture_default_str();
  cmd->add_option("--tasks", o->tasks, "wall, free")->check(CLI::IsMember({"wall", "free"}))->capture_default_str();
  cmd->add_option("--architecture", o->architecture, "position_force or position_position")
      ->check(CLI::IsMember({"position_force", "position_position"}))
      ->capture_default_str();
  cmd->add_option("--jitter", o->jitter_ms, "each packet's extra delay, uniform up to this [ms]")
      ->check(CLI::Range(0.0, 1000.0))
      ->capture_default_str();
  cmd->add_option("--duration", o->duration_s, "each run [s]")->check(CLI::Range(4.0, 600.0))->capture_default_str();
  cmd->add_option("--stiffness", o->stiffness,
                  "the remote's position controller or the coupling [N/m] (default: the pair's sessions', 1500; "
                  "--dof 6: 800)")
      ->check(CLI::Range(0.0, 1e5));
  cmd->add_option("--damping", o->damping, "its damping [N s/m] (default: 20; --dof 6: 40)")
      ->check(CLI::Range(0.0, 1e4));
  cmd->add_option("--motion-scale", o->motion_scale, "remote motion per master motion")
      ->check(CLI::Range(0.01, 100.0))
      ->capture_default_str();
  cmd->add_option(
      "--trace-round-trip", o->trace_round_trip_ms,
      "the wall's run over time at this round-trip delay (one of --round-trips; at the lowest loss run) goes "
      "into the report [ms]; default: the round trip run nearest to 200 ms");
  cmd->add_option("--table", o->table, "also write the rows alone to this JSON file");
  cmd->add_option("--dof", o->dof,
                  "3: the ViSHaRD3 pair in translation; 6: the ViSHaRD6 pair in six degrees of freedom (the operator "
                  "also turns the handle; the remote's plate meets its wall)")
      ->check(CLI::IsMember({3, 6}))
      ->capture_default_str();
  cmd->add_option("--force-scale", o->force_scale, "master force per remote force")
      ->check(CLI::Range(0.01, 100.0))
      ->capture_default_str();
  cmd->callback([o, &exit_code] {
    Options run_options = *o;
    if (run_options.common.quick) {
      run_options.round_trips_ms = {0.0, 200.0};
      run_options.losses_percent = {0.0, 20.0};
      run_options.duration_s = 4.0;
      run_options.tasks = {"wall"};
    }
    exit_code = run(run_options);
  });
}

}  // namespace hapticd::eval
