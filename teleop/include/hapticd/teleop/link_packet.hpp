#pragma once
// What one side of a teleoperation link sends the other every cycle (docs/teleoperation.md). Fixed-size: copying
// it never allocates. Positions are each side's handle from where it was when the link started, in its world
// axes; the master scales its motion to the remote's (motion_scale) before it sends it, so both sides' packets
// speak the remote's units of motion. Energies are each sender's own: the receiver converts them.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

namespace hapticd::teleop {

struct LinkPacket {
  std::uint64_t sequence = 0;  // the sender's count, from 1; a receiver keeps only the newest
  std::int64_t sent_ns = 0;    // the sender's clock when it was sent
  // The packet that arrived at the sender last before it sent this one, newest or not (link_clock.hpp): its sent_ns
  // (the receiver's clock) and when it arrived (the sender's clock). None before a timed packet has arrived.
  bool has_echo = false;
  std::int64_t echo_sent_ns = 0;
  std::int64_t echo_received_ns = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // [m]
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // [m/s]
  // The remote: the force its environment applies to its handle (its sensor), [N]; the master: zero.
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  // Wave variables: the master's u, the remote's w [sqrt(W)]; zero in the other schemes.
  Eigen::Vector3d wave = Eigen::Vector3d::Zero();
  // The energy that has entered the link at the sender's port since the link started [J], never decreasing:
  // a lost or late packet leaves the receiver with less than was sent, never more (time-domain passivity).
  double energy_in = 0.0;
  // Six degrees of freedom (LinkSettings::rotation; else identity and zeros): the handle's rotation since the link
  // started (world axes), its angular velocity [rad/s], the remote's environment's torque [N m] and the energy that
  // entered rotation's port [J] (a port of its own, never decreasing).
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
  double rotation_energy_in = 0.0;
  bool stopped = false;  // the sender's device is stopped (E-stop, fault): the receiver stops too
};

}  // namespace hapticd::teleop
