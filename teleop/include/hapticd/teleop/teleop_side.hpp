#pragma once
// One side of a bilateral teleoperation link (docs/teleoperation.md): the master (the device the operator holds)
// or the remote (the manipulator in the remote environment). Each cycle it takes its device's handle - position,
// velocity and the force the environment applies to it - and the newest packet from the other side, and gives
// the force to apply to its handle and the packet to send. Architectures:
//   - position-force: the master sends its motion; the remote's setpoint follows it through a position
//     controller (a spring-damper to the handle) and returns the force its environment applies; the master
//     displays that force;
//   - position-position: each side sends its motion, and a spring-damper across the link pulls each handle
//     towards the other's.
// Passivity: none (the delayed link as it is); the time-domain passivity approach (an EnergyPort each side, the
// energy that entered at each port carried in the packets); or wave variables (position-force only: the master's
// motion and the remote's force travel as waves, which a delay cannot make active; a lost wave is read as zero).
// Scaling: the remote moves motion_scale times the master's motion; the master feels force_scale times the
// remote's force. Six degrees of freedom (`rotation`): the handle's orientation and angular velocity go over the
// link as well and the torques come back, by the same architecture as the translation (position-position: a
// rotational spring-damper across the link; position-force: the remote's orientation setpoint follows the master's
// rotation and the environment's torque comes back); rotation is not scaled (the master feels force_scale times the
// remote's torque). Rotation has an energy port of its own (its energy in travels as rotation_energy_in) so that
// neither part of the link can pay for the other: each is passive, and so is their sum. Everything runs on the
// caller's thread without allocating.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <string>

#include "hapticd/teleop/energy_port.hpp"
#include "hapticd/teleop/link_clock.hpp"
#include "hapticd/teleop/link_packet.hpp"

namespace hapticd::teleop {

enum class Role { master, remote };
enum class Architecture { position_force, position_position };
enum class Passivity { none, tdpa, wave };

struct LinkSettings {
  Architecture architecture = Architecture::position_force;
  Passivity passivity = Passivity::tdpa;
  double motion_scale = 1.0;  // remote motion per master motion
  double force_scale = 1.0;   // master force per remote force
  // Position-position: the coupling across the link; position-force: the remote's position controller.
  double stiffness = 1500.0;     // [N/m]
  double damping = 20.0;         // [N s/m]
  double wave_impedance = 40.0;  // wave variables' b [N s/m]
  // Position-force: the remote's setpoint closes its distance to the master's motion over this time (drift
  // compensation, paid from the energy budget like all of the setpoint's motion).
  double drift_time_s = 0.02;
  double max_speed = 1.0;   // the remote setpoint's speed limit [m/s]
  double max_force = 40.0;  // the force either side commands at most [N]
  // No packet for this long: the link is lost (the remote's setpoint holds still; the master's force fades out
  // over fade_s, and in again over fade_s when packets come back).
  double link_timeout_s = 1.0;
  double fade_s = 0.1;
  // Six degrees of freedom: orientation, angular velocity and torque over the link too (TDPA or none: wave
  // variables carry translation only). Position-position: the coupling's rotational spring-damper; position-force:
  // the remote's orientation controller. Its setpoint closes its rotation from the master's over drift_time_s.
  bool rotation = false;
  double rotational_stiffness = 2.0;  // [N m/rad]
  double rotational_damping = 0.05;   // [N m s/rad]
  double max_angular_speed = 3.0;     // the remote setpoint's [rad/s]
  double max_torque = 1.0;            // either side commands at most [N m]
};

// The settings' first problem ("" when there is none).
std::string link_settings_problem(const LinkSettings& settings);
const char* to_string(Architecture a) noexcept;
const char* to_string(Passivity p) noexcept;

struct LocalSample {
  std::int64_t time_ns = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // the handle (world) [m]
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // [m/s]
  Eigen::Vector3d force = Eigen::Vector3d::Zero();     // the environment's force on the handle (the remote) [N]
  // With rotation: the handle's orientation (world), angular velocity [rad/s] and the environment's torque [N m].
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
};

struct SideOutput {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   // to apply to the local handle [N]
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  // [N m] (zero without rotation)
  LinkPacket packet;                                 // to send
};

struct SideStatus {
  const EnergyPort* port = nullptr;           // translation's
  const EnergyPort* rotation_port = nullptr;  // rotation's (its energies stay zero without rotation)
  // The other port's energy in, in this side's units [J]: as its packets claim it, and as credited - no more than
  // the link's own force and motion at that port could have carried (a peer's claim is never taken on trust). The
  // passivity controller spends only what is credited.
  double peer_energy_in = 0.0;
  double peer_energy_credited = 0.0;
  double peer_rotation_energy_in = 0.0;  // the same for rotation's ports
  double peer_rotation_energy_credited = 0.0;
  std::uint64_t received = 0;  // packets taken
  std::uint64_t stale = 0;     // packets not newer than one already taken (reordered, or a serial gone back): ignored
  std::uint64_t peers = 0;     // senders the side has taken packets from (peer_changed: one more)
  double silence_s = 0.0;      // since the newest packet arrived (from the start: since the link started)
  bool link_lost = false;      // silence_s > link_timeout_s after the first packet
  bool waiting = false;        // no packet yet for longer than link_timeout_s (not lost: never up)
  bool peer_stopped = false;
  double fade = 1.0;  // the master's force weight: falls to 0 over fade_s while the link is lost, rises when back
  // Position-force, the remote: its setpoint's distance from the master's motion as last received [m].
  double drift_m = 0.0;
  double rotation_drift_rad = 0.0;  // and its orientation setpoint's angle from the master's rotation
  // The link's round trip, the peer's clock offset and the one-way delays, from the packets' times (timed
  // packets only: receive() with their arrival).
  LinkClockFigures clock;
};

class TeleopSide {
 public:
  // Throws std::invalid_argument with link_settings_problem().
  TeleopSide(Role role, const LinkSettings& settings);

  // The link starts at the handle's present position (both sides' motions are taken from here).
  void start(const LocalSample& sample) noexcept;
  // The side goes on from the handle's present position as if it were where the peer's last packet puts it (after
  // the device was stopped and recovered: no pull towards where the peer went meanwhile). The energies go on.
  void rebase(const LocalSample& sample) noexcept;
  // A packet from the other side (any order; only the newest by sequence is kept: serial-number arithmetic, RFC
  // 1982, so a serial that wraps goes on and one far ahead - 2^64-1 after 100 - is older, not newer).
  // `arrival_ns`: when it arrived, on the clock of this side's samples (kUntimed: not known - no delay measured
  // from it, and this side's packets echo none).
  static constexpr std::int64_t kUntimed = INT64_MIN;
  void receive(const LinkPacket& packet, std::int64_t arrival_ns = kUntimed) noexcept;
  // The packets come from another sender from now on (its server restarted: the link's owner re-bound it): its
  // serials and its energy count start afresh, and the side re-anchors at its first packet (no pull towards
  // where the new sender's motion starts). The energy credited so far stays.
  void peer_changed() noexcept;
  // One cycle of dt seconds. `stopped`: this side's device is stopped (the other side is told to stop too).
  SideOutput cycle(const LocalSample& sample, double dt, bool stopped = false) noexcept;

  [[nodiscard]] const SideStatus& status() const noexcept { return status_; }
  [[nodiscard]] Role role() const noexcept { return role_; }
  [[nodiscard]] const LinkSettings& settings() const noexcept { return settings_; }
  // The remote's setpoint (position-force; its start frame) [m].
  [[nodiscard]] const Eigen::Vector3d& setpoint() const noexcept { return setpoint_; }

 private:
  // What the peer's energy in is credited at: what earlier senders were credited, and what the bound has let in
  // since this one came (its units) [J].
  struct Budget {
    double before = 0.0;
    double bound = 0.0;
  };

  Eigen::Vector3d master_force(const Eigen::Vector3d& x, const Eigen::Vector3d& v, double dt, LinkPacket& out) noexcept;
  Eigen::Vector3d remote_force(const Eigen::Vector3d& x, const Eigen::Vector3d& v, const Eigen::Vector3d& f_env,
                               double dt, LinkPacket& out) noexcept;
  // Rotation's counterparts: the handle's orientation from the link's start (world axes) and angular velocity.
  Eigen::Vector3d master_torque(const Eigen::Quaterniond& q, const Eigen::Vector3d& w, double dt,
                                LinkPacket& out) noexcept;
  Eigen::Vector3d remote_torque(const Eigen::Quaterniond& q, const Eigen::Vector3d& w, const Eigen::Vector3d& t_env,
                                double dt, LinkPacket& out) noexcept;
  // The energy scale from the remote's units to the master's: force_scale / motion_scale (rotation: force_scale).
  [[nodiscard]] double to_master_units() const noexcept { return settings_.force_scale / settings_.motion_scale; }

  // The power the peer's port can take in at most, as its newest packet shows it (its units) [W].
  [[nodiscard]] double peer_power_bound() const noexcept;
  [[nodiscard]] double peer_rotation_power_bound() const noexcept;
  // The peer's energy in as credited (its units): claimed, within what the bound has let in since the peer came.
  [[nodiscard]] double credited(const Budget& budget, double claimed) const noexcept {
    return budget.before + (have_peer_ ? std::min(claimed, budget.bound) : 0.0);
  }

  Role role_;
  LinkSettings settings_;
  EnergyPort port_;
  EnergyPort rotation_port_;
  SideStatus status_;
  bool started_ = false;
  bool rebase_pending_ = false;  // peer_changed: re-anchor at the next cycle with a packet
  Budget translation_budget_, rotation_budget_;
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation_origin_ = Eigen::Quaterniond::Identity();
  std::uint64_t sequence_ = 0;
  LinkPacket peer_;  // the newest packet taken
  // The packet that arrived last (newest or not: each arrival is a measurement of the way here) - its send time and
  // arrival, which this side's packets echo.
  std::int64_t echo_sent_ns_ = 0;
  std::int64_t echo_arrival_ns_ = kUntimed;
  LinkClock clock_;
  bool have_peer_ = false;
  // Waves arrived since the last cycle (their mean is this cycle's wave; none: zero).
  Eigen::Vector3d wave_sum_ = Eigen::Vector3d::Zero();
  int waves_ = 0;
  // Position-force, the remote: its setpoint (start frame) and the setpoint's velocity.
  Eigen::Vector3d setpoint_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d setpoint_velocity_ = Eigen::Vector3d::Zero();
  // Its orientation setpoint (from the start, world axes) and angular velocity.
  Eigen::Quaterniond rotation_setpoint_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d rotation_setpoint_velocity_ = Eigen::Vector3d::Zero();
};

}  // namespace hapticd::teleop
