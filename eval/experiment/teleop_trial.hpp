#pragma once
// A teleoperation trial in lockstep (docs/teleoperation.md, "Evaluation"): the master and remote sessions
// (config/sessions/teleoperation/), a TeleopPort each - the server's side of the link with its policies, as its
// TeleopLink runs it - and a ChannelModel each way, stepped cycle by cycle on one virtual clock: each cycle both
// sessions step, each port takes what its channel delivered by then and its device's handle, its force reaches its
// device as an engine's wrench in the next cycle, and a stop it decides is its device's E-stop. The same row and
// seed give the same run.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "hapticd/teleop/channel_model.hpp"
#include "hapticd/teleop/teleop_port.hpp"

namespace hapticd::eval {

enum class TeleopTask {
  wall,  // the operator reaches 6 cm ahead; the remote meets its wall at 3 cm; then the operator pushes harder
  free,  // the operator moves 3 cm back and forth at 0.5 Hz; no wall
};

struct TeleopRow {
  TeleopTask task = TeleopTask::wall;
  double round_trip_s = 0.0;  // the channel's delay, half each way
  double loss = 0.0;          // each way
  double jitter_s = 0.0;      // each way
  teleop::LinkSettings link;
  double duration_s = 6.0;
  double wall_offset_m = 0.03;  // the remote's wall, ahead of its start along x
  std::uint64_t seed = 1;
  bool keep_samples = false;
  // The remote's clock against the master's (no common clock: each server's loop clock): ahead by this at the
  // start and running this much faster. Only the packets' times see it; the delay measurement must see through it.
  double remote_clock_offset_s = 12.5;
  double remote_clock_drift_ppm = 40.0;
  // Every packet either way is lost from outage_start_s for outage_s (a cut link; < 0: none).
  double outage_start_s = -1.0;
  double outage_s = 0.0;
  // Six degrees of freedom: the ViSHaRD6 pair (master6.yaml, remote6.yaml; link.rotation must be on). The operator
  // also turns the handle about z: the wall task to 0.15 rad from 1.5 s, tilting the remote's plate against its wall;
  // free motion 0.2 rad back and forth with the motion.
  bool six_dof = false;
};

struct TeleopSample {
  double t = 0.0;
  Eigen::Vector3d master = Eigen::Vector3d::Zero();  // handles from their start [m]
  Eigen::Vector3d remote = Eigen::Vector3d::Zero();
  Eigen::Vector3d master_force = Eigen::Vector3d::Zero();  // the link's force on the master [N]
  Eigen::Vector3d remote_force = Eigen::Vector3d::Zero();  // on the remote
  Eigen::Vector3d environment = Eigen::Vector3d::Zero();   // the remote's environment on its handle (sensor)
  double energy = 0.0;                                     // the link's stored energy as observed (master units)
  double master_angle = 0.0, remote_angle = 0.0;  // six degrees of freedom: each handle's rotation about z [rad]
  double master_torque = 0.0;                     // the link's torque on the master about z [N m]
};

struct TeleopResult {
  std::string fault;            // a device's fault ("" none): the run ended there
  std::string stop_code;        // a port stopped its device ("" none): why (teleop/teleop_port.hpp)
  double min_energy_j = 0.0;    // the observed energy at its lowest, translation and rotation each (< 0: created)
  bool passive = false;         // min_energy_j >= -1 mJ
  bool stable = false;          // no fault and no sustained or growing oscillation (below)
  double oscillation_mm = 0.0;  // the wall task: the master's peak to peak in the last 1.5 s about its trend;
                                // free motion: the remote's amplitude over the master's
  // The wall task: the force felt at the master over its depth past the wall (the remote's wall over the motion
  // scale), both averaged over the contact from 3 s on; 0 when no contact was felt, NaN when the run was unstable.
  double felt_stiffness_n_per_m = 0.0;
  // Free motion: the remote's mean position minus the master's (scaled) over the last 2 s (one period of the
  // operator's motion); NaN for the wall, where the two differ by the contact's deflection, not by drift.
  double drift_mm = 0.0;
  // Six degrees of freedom: the wall task's torque felt at the master about z over its rotation (both averaged over
  // the contact from 3 s on; NaN when unstable), and the rotation's peak to peak in the last 1.5 s about its trend;
  // free motion: the remote's rotation's amplitude over the master's. NaN for a translation-only row.
  double felt_rotational_stiffness_n_m_per_rad = std::nan("");
  double rotation_oscillation = std::nan("");
  double max_torque_n_m = 0.0;  // on the master
  double max_force_n = 0.0;     // on the master
  double dissipated_j = 0.0;    // by the passivity controllers, both sides
  teleop::ChannelCounters to_remote, to_master;
  // The one-way delays each way: the channel's true mean over the packets delivered (each from its send to the
  // cycle that took it) and each side's measurement from the packets' times (teleop/link_clock.hpp); the remote's
  // clock offset at the end, true and as the master measured it [s].
  struct Delays {
    double true_to_remote_s = 0.0, true_to_master_s = 0.0;
    teleop::LinkClockFigures master, remote;  // master: in = to the master, out = to the remote
    double true_offset_s = 0.0;
    // The largest difference of a measured mean one-way delay (either side, either way) from the true one [s].
    double largest_error_s = 0.0;
  } delays;
  std::vector<TeleopSample> samples;  // with keep_samples: every cycle
};

// `config_dir`: where master.yaml and remote.yaml (master6.yaml and remote6.yaml) are (config/sessions/teleoperation);
// `plugin_paths` are searched for plugins first. Throws std::runtime_error when a session cannot be built,
// std::invalid_argument for a bad row.
TeleopResult run_teleop_trial(const TeleopRow& row, const std::filesystem::path& config_dir,
                              const std::vector<std::filesystem::path>& plugin_paths = {});

const char* to_string(TeleopTask task) noexcept;

// The link as the pair's sessions set it (config/sessions/teleoperation/master.yaml; six_dof: master6.yaml): the
// ViSHaRD6 pair couples more softly and with more damping (with the ViSHaRD3's 1500 N/m it oscillates at 200-500 ms
// round trip and its remote faults), and in rotation.
teleop::LinkSettings pair_link(bool six_dof);

}  // namespace hapticd::eval
