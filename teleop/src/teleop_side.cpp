#include "hapticd/teleop/teleop_side.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hapticd/teleop/rotation.hpp"

namespace hapticd::teleop {
namespace {

Eigen::Vector3d clamp_norm(const Eigen::Vector3d& v, double limit) noexcept {
  const double n = v.norm();
  return n > limit ? Eigen::Vector3d(v * (limit / n)) : v;
}

}  // namespace

std::string link_settings_problem(const LinkSettings& s) {
  const auto bad = [](double v, double lo, double hi) { return !std::isfinite(v) || v < lo || v > hi; };
  if (bad(s.motion_scale, 0.01, 100.0)) return "motion_scale must be in [0.01, 100]";
  if (bad(s.force_scale, 0.01, 100.0)) return "force_scale must be in [0.01, 100]";
  if (bad(s.stiffness, 0.0, 1e5)) return "stiffness must be in [0, 100000] N/m";
  if (bad(s.damping, 0.0, 1e4)) return "damping must be in [0, 10000] N s/m";
  if (bad(s.wave_impedance, 0.1, 1e4)) return "wave_impedance must be in [0.1, 10000] N s/m";
  if (bad(s.drift_time_s, 1e-4, 10.0)) return "drift_time_s must be in [0.0001, 10] s";
  if (bad(s.max_speed, 1e-3, 10.0)) return "max_speed must be in [0.001, 10] m/s";
  if (bad(s.max_force, 0.0, 1000.0)) return "max_force must be in [0, 1000] N";
  if (bad(s.link_timeout_s, 1e-3, 60.0)) return "link_timeout_s must be in [0.001, 60] s";
  if (bad(s.fade_s, 0.0, 10.0)) return "fade_s must be in [0, 10] s";
  if (bad(s.rotational_stiffness, 0.0, 1e4)) return "rotational_stiffness must be in [0, 10000] N m/rad";
  if (bad(s.rotational_damping, 0.0, 1e3)) return "rotational_damping must be in [0, 1000] N m s/rad";
  if (bad(s.max_angular_speed, 1e-3, 100.0)) return "max_angular_speed must be in [0.001, 100] rad/s";
  if (bad(s.max_torque, 0.0, 1000.0)) return "max_torque must be in [0, 1000] N m";
  if (s.rotation && s.passivity == Passivity::wave)
    return "wave variables carry translation only (with rotation: passivity tdpa or none)";
  if (s.passivity == Passivity::wave && s.architecture != Architecture::position_force)
    return "wave variables carry the position-force architecture only (passivity: tdpa or none for position-position)";
  return "";
}

const char* to_string(Architecture a) noexcept {
  return a == Architecture::position_force ? "position_force" : "position_position";
}

const char* to_string(Passivity p) noexcept {
  switch (p) {
    case Passivity::none:
      return "none";
    case Passivity::tdpa:
      return "tdpa";
    case Passivity::wave:
      return "wave";
  }
  return "?";
}

TeleopSide::TeleopSide(Role role, const LinkSettings& settings) : role_(role), settings_(settings) {
  if (const std::string problem = link_settings_problem(settings); !problem.empty())
    throw std::invalid_argument("teleoperation: " + problem);
  status_.port = &port_;
  status_.rotation_port = &rotation_port_;
}

void TeleopSide::start(const LocalSample& sample) noexcept {
  started_ = true;
  origin_ = sample.position;
  orientation_origin_ = sample.orientation.normalized();
  setpoint_.setZero();
  setpoint_velocity_.setZero();
  rotation_setpoint_.setIdentity();
  rotation_setpoint_velocity_.setZero();
}

void TeleopSide::rebase(const LocalSample& sample) noexcept {
  // The peer's position in this side's frame: the master's packets are in the remote's units already.
  const Eigen::Vector3d peer = have_peer_ ? peer_.position : Eigen::Vector3d::Zero();
  origin_ = sample.position - (role_ == Role::master ? Eigen::Vector3d(peer / settings_.motion_scale) : peer);
  setpoint_ = peer;
  setpoint_velocity_.setZero();
  // Rotation is not scaled: this side's rotation from the start becomes the peer's.
  const Eigen::Quaterniond peer_rotation = have_peer_ ? peer_.orientation : Eigen::Quaterniond::Identity();
  orientation_origin_ = (peer_rotation.conjugate() * sample.orientation).normalized();
  rotation_setpoint_ = peer_rotation;
  rotation_setpoint_velocity_.setZero();
  started_ = true;
}

void TeleopSide::receive(const LinkPacket& packet, std::int64_t arrival_ns) noexcept {
  // Every timed exchange measures the link, a stale packet's too (it took the way it took).
  if (arrival_ns != kUntimed && packet.has_echo) {
    clock_.exchange(packet.echo_sent_ns, packet.echo_received_ns, packet.sent_ns, arrival_ns);
    status_.clock = clock_.figures();
  }
  if (arrival_ns != kUntimed) {
    echo_sent_ns_ = packet.sent_ns;
    echo_arrival_ns_ = arrival_ns;
  }
  if (have_peer_ && static_cast<std::int64_t>(packet.sequence - peer_.sequence) <= 0) {
    ++status_.stale;
    return;
  }
  if (!have_peer_) ++status_.peers;
  peer_ = packet;
  have_peer_ = true;
  ++status_.received;
  status_.silence_s = 0.0;
  if (settings_.passivity == Passivity::wave) {
    wave_sum_ += packet.wave;
    ++waves_;
  }
}

void TeleopSide::peer_changed() noexcept {
  translation_budget_ = {credited(translation_budget_, peer_.energy_in), 0.0};
  rotation_budget_ = {credited(rotation_budget_, peer_.rotation_energy_in), 0.0};
  have_peer_ = false;
  peer_ = LinkPacket{};
  echo_arrival_ns_ = kUntimed;
  clock_.reset();  // another peer, another clock
  status_.clock = clock_.figures();
  rebase_pending_ = true;
}

double TeleopSide::peer_power_bound() const noexcept {
  // What enters the peer's port: the master's, the link's force (at most max_force) against the hand's motion; the
  // remote's (position-force), its environment's force against the setpoint's motion (at most max_speed). Twice
  // that: the packets sample both, and the energy between two samples may come at a higher rate.
  const LinkSettings& s = settings_;
  const double bound = role_ == Role::remote ? s.max_force * peer_.velocity.norm() / s.motion_scale
                       : s.architecture == Architecture::position_force ? peer_.force.norm() * s.max_speed
                                                                        : s.max_force * peer_.velocity.norm();
  return 2.0 * bound;
}

double TeleopSide::peer_rotation_power_bound() const noexcept {
  // As peer_power_bound, for rotation (not scaled).
  const LinkSettings& s = settings_;
  const double bound = role_ == Role::remote                            ? s.max_torque * peer_.angular_velocity.norm()
                       : s.architecture == Architecture::position_force ? peer_.torque.norm() * s.max_angular_speed
                                                                        : s.max_torque * peer_.angular_velocity.norm();
  return 2.0 * bound;
}

SideOutput TeleopSide::cycle(const LocalSample& sample, double dt, bool stopped) noexcept {
  if (!started_) start(sample);
  if (rebase_pending_ && have_peer_) {
    rebase(sample);
    rebase_pending_ = false;
  }
  // The bound grows with the peer's newest motion and force while its packets come.
  if (have_peer_ && status_.silence_s <= settings_.link_timeout_s) {
    translation_budget_.bound += peer_power_bound() * dt;
    rotation_budget_.bound += peer_rotation_power_bound() * dt;
  }
  SideOutput out;
  const Eigen::Vector3d x = sample.position - origin_;
  const Eigen::Vector3d& v = sample.velocity;
  status_.silence_s += dt;
  // Lost only once it was up: before the peer's first packet the link is waiting (the remote's setpoint holds, the
  // master has nothing to render) - a pair whose discovery takes longer than the timeout does not stop at start.
  status_.waiting = status_.received == 0 && status_.silence_s > settings_.link_timeout_s;
  status_.link_lost = status_.received > 0 && status_.silence_s > settings_.link_timeout_s;
  status_.peer_stopped = have_peer_ && peer_.stopped;

  // A lost link or a stopped side: the master's force fades out (the remote's setpoint stops: remote_force). The
  // weight falls over fade_s and rises again over fade_s when the link is back: no jolt either way.
  const bool hold = status_.link_lost || status_.peer_stopped || stopped;
  const double step = settings_.fade_s > 0.0 ? dt / settings_.fade_s : 1.0;
  status_.fade = std::clamp(status_.fade + (hold ? -step : step), 0.0, 1.0);

  out.force =
      role_ == Role::master ? master_force(x, v, dt, out.packet) : remote_force(x, v, sample.force, dt, out.packet);
  if (settings_.rotation) {
    const Eigen::Quaterniond q = (sample.orientation.normalized() * orientation_origin_.conjugate()).normalized();
    const Eigen::Vector3d& w = sample.angular_velocity;
    out.torque = role_ == Role::master ? master_torque(q, w, dt, out.packet)
                                       : remote_torque(q, w, sample.torque, dt, out.packet);
  }
  wave_sum_.setZero();
  waves_ = 0;
  out.packet.sequence = ++sequence_;
  out.packet.sent_ns = sample.time_ns;
  out.packet.has_echo = echo_arrival_ns_ != kUntimed;
  out.packet.echo_sent_ns = out.packet.has_echo ? echo_sent_ns_ : 0;
  out.packet.echo_received_ns = out.packet.has_echo ? echo_arrival_ns_ : 0;
  out.packet.energy_in = port_.energy_in();
  out.packet.rotation_energy_in = rotation_port_.energy_in();
  out.packet.stopped = stopped;
  return out;
}

Eigen::Vector3d TeleopSide::master_force(const Eigen::Vector3d& x, const Eigen::Vector3d& v, double dt,
                                         LinkPacket& out) noexcept {
  const LinkSettings& s = settings_;
  const double c = to_master_units();
  const Eigen::Vector3d xs = s.motion_scale * x;  // in the remote's units of motion
  const Eigen::Vector3d vs = s.motion_scale * v;
  out.position = xs;
  out.velocity = vs;
  status_.peer_energy_in = (translation_budget_.before + peer_.energy_in) * c;
  status_.peer_energy_credited = credited(translation_budget_, peer_.energy_in) * c;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  if (s.passivity == Passivity::wave) {
    // The force on the link in the remote's units, f = b v - sqrt(2b) w, sent as u = (b v + f) / sqrt(2b).
    const double b = s.wave_impedance;
    const Eigen::Vector3d w = waves_ > 0 ? Eigen::Vector3d(wave_sum_ / waves_) : Eigen::Vector3d::Zero();
    Eigen::Vector3d f = b * vs - std::sqrt(2.0 * b) * w;
    f = clamp_norm(f, s.max_force / s.force_scale);
    out.wave = (b * vs + f) / std::sqrt(2.0 * b);
    force = -s.force_scale * status_.fade * f;
    return port_.force_out(force, v, dt, status_.peer_energy_credited, false);
  }
  // While the link is lost the last packet's force (or spring) fades out; the port sees what is applied.
  if (have_peer_) {
    if (s.architecture == Architecture::position_force) {
      force = s.force_scale * peer_.force;
    } else {
      force = s.force_scale * (s.stiffness * (peer_.position - xs) + s.damping * (peer_.velocity - vs));
    }
  }
  force = status_.fade * clamp_norm(force, s.max_force);
  return port_.force_out(force, v, dt, status_.peer_energy_credited, s.passivity == Passivity::tdpa);
}

Eigen::Vector3d TeleopSide::remote_force(const Eigen::Vector3d& x, const Eigen::Vector3d& v,
                                         const Eigen::Vector3d& f_env, double dt, LinkPacket& out) noexcept {
  const LinkSettings& s = settings_;
  const double c = to_master_units();
  out.position = x;
  out.velocity = v;
  out.force = f_env;
  status_.peer_energy_in = (translation_budget_.before + peer_.energy_in) / c;
  status_.peer_energy_credited = credited(translation_budget_, peer_.energy_in) / c;
  const bool follow = have_peer_ && !status_.link_lost && !peer_.stopped;
  if (s.architecture == Architecture::position_position) {
    Eigen::Vector3d force = Eigen::Vector3d::Zero();
    if (follow) force = s.stiffness * (peer_.position - x) + s.damping * (peer_.velocity - v);
    force = clamp_norm(force, s.max_force);
    return port_.force_out(force, v, dt, status_.peer_energy_credited, s.passivity == Passivity::tdpa);
  }
  // Position-force: the link moves the setpoint; the environment's force on the handle pushes back on it.
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  if (s.passivity == Passivity::wave) {
    // v = (sqrt(2b) u - f) / b with f = -f_env the force the link exerts on the setpoint; w = (b v - f) / sqrt(2b).
    const double b = s.wave_impedance;
    const Eigen::Vector3d u = waves_ > 0 ? Eigen::Vector3d(wave_sum_ / waves_) : Eigen::Vector3d::Zero();
    const Eigen::Vector3d f = -f_env;
    velocity = follow ? Eigen::Vector3d((std::sqrt(2.0 * b) * u - f) / b) : Eigen::Vector3d::Zero();
    velocity = clamp_norm(velocity, s.max_speed);
    out.wave = (b * velocity - f) / std::sqrt(2.0 * b);
    velocity = port_.velocity_out(velocity, f_env, dt, status_.peer_energy_credited, false);
  } else {
    if (follow) {
      velocity = peer_.velocity + (peer_.position - setpoint_) / s.drift_time_s;
      velocity = clamp_norm(velocity, s.max_speed);
    }
    velocity = port_.velocity_out(velocity, f_env, dt, status_.peer_energy_credited, s.passivity == Passivity::tdpa);
  }
  setpoint_velocity_ = velocity;
  setpoint_ += velocity * dt;
  if (have_peer_) status_.drift_m = (peer_.position - setpoint_).norm();
  const Eigen::Vector3d force = s.stiffness * (setpoint_ - x) + s.damping * (setpoint_velocity_ - v);
  return clamp_norm(force, s.max_force);
}

Eigen::Vector3d TeleopSide::master_torque(const Eigen::Quaterniond& q, const Eigen::Vector3d& w, double dt,
                                          LinkPacket& out) noexcept {
  const LinkSettings& s = settings_;
  out.orientation = q;
  out.angular_velocity = w;
  status_.peer_rotation_energy_in = (rotation_budget_.before + peer_.rotation_energy_in) * s.force_scale;
  status_.peer_rotation_energy_credited = credited(rotation_budget_, peer_.rotation_energy_in) * s.force_scale;
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
  if (have_peer_) {
    if (s.architecture == Architecture::position_force) {
      torque = s.force_scale * peer_.torque;
    } else {
      torque = s.force_scale * (s.rotational_stiffness * rotation_between(q, peer_.orientation) +
                                s.rotational_damping * (peer_.angular_velocity - w));
    }
  }
  torque = status_.fade * clamp_norm(torque, s.max_torque);
  return rotation_port_.force_out(torque, w, dt, status_.peer_rotation_energy_credited, s.passivity == Passivity::tdpa);
}

Eigen::Vector3d TeleopSide::remote_torque(const Eigen::Quaterniond& q, const Eigen::Vector3d& w,
                                          const Eigen::Vector3d& t_env, double dt, LinkPacket& out) noexcept {
  const LinkSettings& s = settings_;
  out.orientation = q;
  out.angular_velocity = w;
  out.torque = t_env;
  status_.peer_rotation_energy_in = (rotation_budget_.before + peer_.rotation_energy_in) / s.force_scale;
  status_.peer_rotation_energy_credited = credited(rotation_budget_, peer_.rotation_energy_in) / s.force_scale;
  const bool follow = have_peer_ && !status_.link_lost && !peer_.stopped;
  const bool control = s.passivity == Passivity::tdpa;
  if (s.architecture == Architecture::position_position) {
    Eigen::Vector3d torque = Eigen::Vector3d::Zero();
    if (follow)
      torque = s.rotational_stiffness * rotation_between(q, peer_.orientation) +
               s.rotational_damping * (peer_.angular_velocity - w);
    torque = clamp_norm(torque, s.max_torque);
    return rotation_port_.force_out(torque, w, dt, status_.peer_rotation_energy_credited, control);
  }
  // Position-force: the link turns the setpoint; the environment's torque on the handle pushes back on it.
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();
  if (follow) {
    omega = peer_.angular_velocity + rotation_between(rotation_setpoint_, peer_.orientation) / s.drift_time_s;
    omega = clamp_norm(omega, s.max_angular_speed);
  }
  omega = rotation_port_.velocity_out(omega, t_env, dt, status_.peer_rotation_energy_credited, control);
  rotation_setpoint_velocity_ = omega;
  rotation_setpoint_ = (rotation_of(omega * dt) * rotation_setpoint_).normalized();
  if (have_peer_) status_.rotation_drift_rad = rotation_between(rotation_setpoint_, peer_.orientation).norm();
  const Eigen::Vector3d torque =
      s.rotational_stiffness * rotation_between(q, rotation_setpoint_) + s.rotational_damping * (omega - w);
  return clamp_norm(torque, s.max_torque);
}

}  // namespace hapticd::teleop
