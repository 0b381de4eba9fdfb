#include "teleop_trial.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <tuple>

#include "hapticd/server/session.hpp"
#include "hapticd/teleop/rotation.hpp"

namespace hapticd::eval {
namespace {

using teleop::ChannelModel;
using teleop::ChannelSettings;
using teleop::LinkPacket;
using teleop::LocalSample;
using teleop::Role;
using teleop::TeleopPort;

std::vector<std::string> master_overrides(const TeleopRow& row) {
  const std::string p = "devices.master.device.parameters.";
  std::vector<std::string> o;
  if (row.task == TeleopTask::wall) {
    o = {p + "operator_motion=step", p + "operator_motion_m=[0.06, 0, 0]", p + "operator_motion_start_s=0.3",
         p + "operator_force=ramp",  p + "operator_force_n=[2.0, 0, 0]",   p + "operator_force_start_s=3.0"};
    if (row.six_dof)
      for (const char* r :
           {"operator_rotation=step", "operator_rotation_rad=[0, 0, 0.15]", "operator_rotation_start_s=1.5"})
        o.push_back(p + r);
  } else {
    o = {p + "operator_motion=sine", p + "operator_motion_m=[0.03, 0, 0]", p + "operator_motion_frequency_hz=0.5"};
    if (row.six_dof)
      for (const char* r :
           {"operator_rotation=sine", "operator_rotation_rad=[0, 0, 0.2]", "operator_rotation_frequency_hz=0.5"})
        o.push_back(p + r);
  }
  return o;
}

// The handle's rotation about z from `start` (world) [rad].
double angle_about_z(const Eigen::Quaterniond& q, const Eigen::Quaterniond& start) {
  return teleop::rotation_between(start, q).z();
}

std::vector<std::string> remote_overrides(const TeleopRow& row) {
  if (row.task == TeleopTask::free) return {"devices.remote.device.parameters.wall_normal=[0, 0, 0]"};
  return {"devices.remote.device.parameters.wall_offset_m=" + std::to_string(row.wall_offset_m)};
}

LocalSample sample_of(const server::DeviceView& v) {
  LocalSample s;
  s.time_ns = std::llround(v.time_s * 1e9);
  s.position = v.handle_pose.position;
  s.velocity = v.handle_twist.linear;
  s.force = v.operator_wrench.force;  // what holds the handle: for the remote, its environment
  s.orientation = v.handle_pose.orientation;
  s.angular_velocity = v.handle_twist.angular;
  s.torque = v.operator_wrench.torque;
  return s;
}

void apply(server::Session& session, const std::string& device, const teleop::PortCycle& out, std::uint64_t seq) {
  EngineInput input;
  input.has_wrench = true;
  input.wrench.force = out.force;
  input.wrench.torque = out.torque;
  input.sequence = seq;
  session.set_engine_input(device, input);
}

// Least-squares slope of y against x.
double slope(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sx += x[i];
    sy += y[i];
    sxx += x[i] * x[i];
    sxy += x[i] * y[i];
  }
  const double d = n * sxx - sx * sx;
  return d > 0.0 ? (n * sxy - sx * sy) / d : 0.0;
}

// Peak to peak of y about its straight-line trend over t.
double detrended_peak_to_peak(const std::vector<double>& t, const std::vector<double>& y) {
  if (t.size() < 2) return 0.0;
  const double k = slope(t, y);
  double mt = 0, my = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    mt += t[i];
    my += y[i];
  }
  mt /= static_cast<double>(t.size());
  my /= static_cast<double>(t.size());
  double lo = std::numeric_limits<double>::max(), hi = -lo;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double r = y[i] - (my + k * (t[i] - mt));
    lo = std::min(lo, r);
    hi = std::max(hi, r);
  }
  return hi - lo;
}

double peak_to_peak(const std::vector<double>& y) {
  if (y.empty()) return 0.0;
  const auto [lo, hi] = std::minmax_element(y.begin(), y.end());
  return *hi - *lo;
}

double mean(const std::vector<double>& y) {
  double s = 0.0;
  for (double v : y) s += v;
  return y.empty() ? 0.0 : s / static_cast<double>(y.size());
}

}  // namespace

const char* to_string(TeleopTask task) noexcept { return task == TeleopTask::wall ? "wall" : "free"; }

teleop::LinkSettings pair_link(bool six_dof) {
  teleop::LinkSettings link;
  if (six_dof) {
    link.stiffness = 800.0;
    link.damping = 40.0;
    link.rotation = true;
    link.rotational_stiffness = 3.0;
    link.rotational_damping = 0.05;
    link.max_torque = 1.5;
  }
  return link;
}

TeleopResult run_teleop_trial(const TeleopRow& row, const std::filesystem::path& config_dir,
                              const std::vector<std::filesystem::path>& plugin_paths) {
  if (!(row.duration_s >= 2.0 && row.duration_s <= 600.0))
    throw std::invalid_argument("teleoperation trial: duration_s must be in [2, 600] s");
  ChannelSettings channel;
  channel.delay_s = row.round_trip_s / 2.0;
  channel.jitter_s = row.jitter_s;
  channel.loss = row.loss;
  channel.seed = row.seed;
  ChannelModel to_remote(channel);
  channel.seed = row.seed ^ 0xA5A5A5A5ULL;
  ChannelModel to_master(channel);
  if (row.six_dof != row.link.rotation)
    throw std::invalid_argument("teleoperation trial: six degrees of freedom take the link's rotation (and only they)");
  TeleopPort master_side(Role::master, row.link);
  TeleopPort remote_side(Role::remote, row.link);

  server::SessionOptions mo{master_overrides(row), plugin_paths};
  mo.overrides.push_back("server.seed=" + std::to_string(row.seed));
  server::SessionOptions ro{remote_overrides(row), plugin_paths};
  ro.overrides.push_back("server.seed=" + std::to_string(row.seed + 1));
  server::Session master = server::Session::from_file(config_dir / (row.six_dof ? "master6.yaml" : "master.yaml"), mo);
  server::Session remote = server::Session::from_file(config_dir / (row.six_dof ? "remote6.yaml" : "remote.yaml"), ro);
  const double dt = master.period_s();
  if (std::abs(remote.period_s() - dt) > 1e-12)
    throw std::invalid_argument("teleoperation trial: the master and the remote must run at one rate");

  TeleopResult result;
  const auto cycles = static_cast<std::uint64_t>(std::llround(row.duration_s / dt));
  const double c = row.link.force_scale / row.link.motion_scale;
  Eigen::Vector3d master_origin, remote_origin;
  Eigen::Quaterniond master_start, remote_start;
  std::vector<double> ts, mx, rx, fx, fpos;  // for the figures of merit
  std::vector<double> ma, ra, mt;            // six degrees of freedom: the rotations about z, the master's torque
  double max_torque = 0.0;
  double min_energy = 0.0;
  double max_force = 0.0;
  // The remote's clock: ahead and faster (the packets' times only). A packet's true send time from its time stamp.
  const double rate = 1.0 + row.remote_clock_drift_ppm * 1e-6;
  const auto offset_ns = std::llround(row.remote_clock_offset_s * 1e9);
  auto remote_clock = [&](std::int64_t t) { return offset_ns + std::llround(static_cast<double>(t) * rate); };
  auto remote_send_time = [&](std::int64_t stamp) {
    return std::llround(static_cast<double>(stamp - offset_ns) / rate);
  };
  double true_sum_to_remote = 0.0, true_sum_to_master = 0.0;
  std::uint64_t true_to_remote = 0, true_to_master = 0;
  for (std::uint64_t k = 1; k <= cycles; ++k) {
    master.step(1);
    remote.step(1);
    const server::DeviceView mv = master.device("master");
    const server::DeviceView rv = remote.device("remote");
    if (k == 1) {
      master_origin = mv.handle_pose.position;
      remote_origin = rv.handle_pose.position;
      master_start = mv.handle_pose.orientation;
      remote_start = rv.handle_pose.orientation;
    }
    if (!mv.fault.empty() || !rv.fault.empty()) {
      result.fault = !mv.fault.empty() ? "master: " + mv.fault : "remote: " + rv.fault;
      break;
    }
    const std::int64_t now = std::llround(mv.time_s * 1e9);
    to_master.deliver(now, [&](const LinkPacket& p) {
      true_sum_to_master += 1e-9 * static_cast<double>(now - remote_send_time(p.sent_ns));
      ++true_to_master;
      master_side.receive(p, now);
    });
    to_remote.deliver(now, [&](const LinkPacket& p) {
      true_sum_to_remote += 1e-9 * static_cast<double>(now - p.sent_ns);
      ++true_to_remote;
      remote_side.receive(p, remote_clock(now));
    });
    LocalSample remote_sample = sample_of(rv);
    remote_sample.time_ns = remote_clock(now);
    const teleop::PortCycle mo_out = master_side.cycle(sample_of(mv), dt, false, false);
    const teleop::PortCycle ro_out = remote_side.cycle(remote_sample, dt, false, false);
    // What the ports decided, done as the server's link does: the force to the device, or its E-stop.
    for (auto [session, name, out] : {std::tuple{&master, "master", &mo_out}, std::tuple{&remote, "remote", &ro_out}}) {
      if (out->apply) apply(*session, name, *out, k);
      if (out->stop != teleop::PortStop::none) {
        if (result.stop_code.empty()) result.stop_code = teleop::stop_code(out->stop);
        server::DeviceRequest estop;
        estop.kind = server::DeviceRequest::Kind::emergency_stop;
        session->request(name, estop);
      }
    }
    const double t = static_cast<double>(k) * dt;
    if (!(row.outage_start_s >= 0.0 && t >= row.outage_start_s && t < row.outage_start_s + row.outage_s)) {
      to_remote.send(mo_out.packet, now);
      to_master.send(ro_out.packet, now);
    }

    const teleop::EnergyPort& pm = *master_side.status().port;
    const teleop::EnergyPort& pr = *remote_side.status().port;
    // Rotation's ports have budgets of their own (rotation is not scaled: the remote's torque counts force_scale
    // times): each part must stay passive by itself - a sum would let one part's surplus hide the other's deficit.
    const teleop::EnergyPort& qm = *master_side.status().rotation_port;
    const teleop::EnergyPort& qr = *remote_side.status().rotation_port;
    const double translation = (pm.energy_in() - pm.energy_out()) + c * (pr.energy_in() - pr.energy_out());
    const double rotation =
        (qm.energy_in() - qm.energy_out()) + row.link.force_scale * (qr.energy_in() - qr.energy_out());
    const double energy = translation + rotation;
    min_energy = std::min({min_energy, translation, rotation});
    max_force = std::max(max_force, mo_out.force.norm());
    max_torque = std::max(max_torque, mo_out.torque.norm());
    const double am = angle_about_z(mv.handle_pose.orientation, master_start);
    const double ar = angle_about_z(rv.handle_pose.orientation, remote_start);
    ma.push_back(am);
    ra.push_back(ar);
    mt.push_back(mo_out.torque.z());
    const Eigen::Vector3d xm = mv.handle_pose.position - master_origin;
    const Eigen::Vector3d xr = rv.handle_pose.position - remote_origin;
    ts.push_back(t);
    mx.push_back(xm.x());
    rx.push_back(xr.x());
    fx.push_back(-mo_out.force.x());
    fpos.push_back(xm.x());
    if (row.keep_samples)
      result.samples.push_back(
          {t, xm, xr, mo_out.force, ro_out.force, rv.operator_wrench.force, energy, am, ar, mo_out.torque.z()});
  }
  TeleopResult::Delays& d = result.delays;
  d.true_to_remote_s = true_to_remote > 0 ? true_sum_to_remote / static_cast<double>(true_to_remote) : 0.0;
  d.true_to_master_s = true_to_master > 0 ? true_sum_to_master / static_cast<double>(true_to_master) : 0.0;
  d.master = master_side.status().clock;
  d.remote = remote_side.status().clock;
  d.true_offset_s =
      1e-9 * static_cast<double>(remote_clock(std::llround(row.duration_s * 1e9)) - std::llround(row.duration_s * 1e9));
  for (const double e : {d.master.mean_delay_in_s - d.true_to_master_s, d.master.mean_delay_out_s - d.true_to_remote_s,
                         d.remote.mean_delay_in_s - d.true_to_remote_s, d.remote.mean_delay_out_s - d.true_to_master_s})
    d.largest_error_s = std::max(d.largest_error_s, std::abs(e));
  result.to_remote = to_remote.counters();
  result.to_master = to_master.counters();
  result.min_energy_j = min_energy;
  result.passive = min_energy >= -1e-3;
  result.max_force_n = max_force;
  result.dissipated_j = master_side.status().port->dissipated() + c * remote_side.status().port->dissipated() +
                        master_side.status().rotation_port->dissipated() +
                        row.link.force_scale * remote_side.status().rotation_port->dissipated();
  result.max_torque_n_m = max_torque;

  // Figures of merit over the run's last part (a run that faulted has no such part: it is unstable).
  const double end = row.duration_s;
  std::vector<double> wt, wm, wr, sx, sf, dm, dr;
  std::vector<double> wam, war, fam, fat, fr_m, fr_r;  // rotation: the last 1.5 s; the contact's; the last 2 s
  for (std::size_t i = 0; i < ts.size(); ++i) {
    if (ts[i] >= end - 1.5) {
      wt.push_back(ts[i]);
      wm.push_back(mx[i]);
      wr.push_back(rx[i]);
      wam.push_back(ma[i]);
      war.push_back(ra[i]);
    }
    if (row.task == TeleopTask::wall && ts[i] >= 3.0 && fx[i] > 0.5) {
      fam.push_back(ma[i]);
      fat.push_back(-mt[i]);
    }
    if (ts[i] >= end - 2.0) {
      fr_m.push_back(ma[i]);
      fr_r.push_back(ra[i]);
    }
    if (ts[i] >= end - 2.0) {
      dm.push_back(row.link.motion_scale * mx[i]);
      dr.push_back(rx[i]);
    }
    if (row.task == TeleopTask::wall && ts[i] >= 3.0 && fx[i] > 0.5) {
      sx.push_back(fpos[i]);
      sf.push_back(fx[i]);
    }
  }
  result.drift_mm = row.task == TeleopTask::free ? 1e3 * (mean(dr) - mean(dm)) : std::nan("");
  if (row.task == TeleopTask::wall) {
    result.oscillation_mm = 1e3 * std::max(detrended_peak_to_peak(wt, wm), detrended_peak_to_peak(wt, wr));
    result.stable = result.fault.empty() && result.oscillation_mm < 5.0;
    if (row.six_dof) {
      result.rotation_oscillation = std::max(detrended_peak_to_peak(wt, wam), detrended_peak_to_peak(wt, war));
      result.stable = result.stable && result.rotation_oscillation < 0.02;
      result.felt_rotational_stiffness_n_m_per_rad = !result.stable                          ? std::nan("")
                                                     : fam.size() >= 200 && mean(fam) > 1e-3 ? mean(fat) / mean(fam)
                                                                                             : 0.0;
    }
    result.felt_stiffness_n_per_m = std::nan("");  // an oscillating contact has no stiffness
    // Force per depth past where the wall is for the master (the remote's wall over the motion scale), averaged
    // over the contact: what the operator feels, however the link's drift has moved the master meanwhile.
    const double wall = row.wall_offset_m / row.link.motion_scale;
    std::vector<double> depth;
    for (const double x : sx) depth.push_back(x - wall);
    if (result.stable)
      result.felt_stiffness_n_per_m = sx.size() >= 200 && mean(depth) > 1e-4 ? mean(sf) / mean(depth) : 0.0;
  } else {
    const double master_p2p = peak_to_peak(dm);
    result.oscillation_mm = master_p2p > 0.0 ? peak_to_peak(dr) / master_p2p : 0.0;  // a ratio here
    result.stable = result.fault.empty() && master_p2p < 0.12 && result.oscillation_mm < 1.5;
    if (row.six_dof) {
      const double turned = peak_to_peak(fr_m);
      result.rotation_oscillation = turned > 0.0 ? peak_to_peak(fr_r) / turned : 0.0;  // a ratio here
      result.stable = result.stable && turned < 1.0 && result.rotation_oscillation < 1.5;
    }
  }
  return result;
}

}  // namespace hapticd::eval
