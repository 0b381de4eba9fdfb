#pragma once
// The evaluation rig: one simulated device, what holds its handle, and the control scheme under test, built as
// a session file and run through the public session API in lockstep (deterministic, independent of the
// machine's speed). Every experiment describes its run with a RigSpec; the schemes are the thesis's
// (scheme.hpp).
#include <functional>
#include <string>
#include <vector>

#include "hapticd/server/session.hpp"
#include "scheme.hpp"

namespace hapticd::eval {

// The simulated device of a rig: which shipped device, where its joints start, and the simulator's effects
// (extra `key: value` lines for the sim plugin's parameters, for instance to switch an effect off).
struct RigDevice {
  std::string name = "vishard3";            // vishard3, vishard6, vishard10
  std::vector<double> initial_position;     // empty: the device preset's rig position
  std::vector<std::string> sim_parameters;  // "key: value" added to the sim plugin's parameters
  // What the controllers know of it: admittance display's inner loops compensate its identified friction (the
  // thesis's `+ h`, the controllers' friction_compensation with the preset's friction file; a device without
  // one runs uncompensated).
  bool friction_compensation = true;
};

struct RigSpec {
  RigDevice device;
  Scheme scheme;
  // What the scheme renders: the scripted_wrench model's parameters ("key: value" lines; signal, force_n, ...),
  // empty: the scheme's own model (the virtual admittance of an admittance scheme; nothing for impedance).
  std::vector<std::string> script;
  // More parameters of the virtual model ("walls: [...]", "wall_stiffness_n_per_m: 5000", "mass_kg: [...]"):
  // a key given here replaces the rig's default (the scheme's mass, zero damping). In impedance display they
  // make the rig render with the scripted_wrench model (its walls act on the measured handle motion).
  std::vector<std::string> model;
  // Another virtual model in place of the scheme's ("trajectory": its parameters are `model`, nothing else).
  std::string model_plugin;
  // The sim plugin's attachment parameters ("attachment: position_source", "source_path: shuttle", ...).
  std::vector<std::string> attachment;
  std::uint64_t seed = 1;
};

// The duration of one leg of the sim's `shuttle` path (docs/simulated-devices.md): accelerate, cruise, decelerate
// over `distance` (triangular when too short to reach `speed`).
[[nodiscard]] double shuttle_leg_s(double distance, double acceleration, double speed);

// The session file text of a rig (for the report, and to reproduce a run with `hapticd --lockstep`).
std::string rig_yaml(const RigSpec& spec);
// The session; throws std::runtime_error with the session's error when it cannot be built.
server::Session make_rig_session(const RigSpec& spec);

// One cycle of a run, as the experiments analyse it (world frame, handle point).
struct RigSample {
  double t = 0.0;
  Eigen::Vector3d commanded_force = Eigen::Vector3d::Zero();   // what the scheme renders (TaskTarget::wrench)
  Eigen::Vector3d measured_force = Eigen::Vector3d::Zero();    // the device's force on what holds it: -F_h (sensor)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();          // the handle (measured joints)
  Eigen::Vector3d desired_position = Eigen::Vector3d::Zero();  // the virtual model's target (admittance display)
  Eigen::Vector3d true_velocity = Eigen::Vector3d::Zero();     // the simulation's truth
  Eigen::Vector3d true_angular_velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d true_force = Eigen::Vector3d::Zero();  // the truth: what holds the handle applies to it
  JointVector torque;                                    // written
};

// Runs `cycles` cycles and calls `sample` after each with the cycle's sample; stops early (returning the
// fault) when the device faults. Returns "" when every cycle ran.
std::string run_rig(server::Session& session, std::uint64_t cycles,
                    const std::function<void(const RigSample&)>& sample);

}  // namespace hapticd::eval
