#pragma once
// The stability trials of the minimum-inertia and Z-width experiments (docs/evaluation.md, "Stability
// criterion"): standardized operator loads - the simulated operator with a loose or a firm grasp, voluntary
// motion, a hard collision with a virtual wall - and one criterion, the same for every scheme and device:
//   a trial is stable when the device does not fault and, over the last `window_s` of the run, the RMS of the
//   handle's true velocity above `cutoff_hz` (all three axes together) stays below `threshold_m_s`;
//   a collision is stable when the device does not fault and the operator never gets back more energy than it
//   gave (its work on the handle never below -`collision_tolerance_j`): a heavy virtual mass pushed by a soft
//   hand bounces on a stiff wall for seconds, passively, which the velocity measure would call an oscillation.
// The cutoff lies above the operator's voluntary motion (0.5 Hz) and below the lowest oscillation the schemes
// show (about 5 Hz); the threshold is a visible oscillation (0.02 m/s RMS is 0.4 mm at 8 Hz). On a device that
// renders rotations too (ViSHaRD6, ViSHaRD10) the handle's angular velocity above the cutoff is held to
// `rotational_threshold_rad_s` the same way (0.2 rad/s RMS is 4 mrad at 8 Hz: 0.4 mm at a 10 cm grip).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "report/json.hpp"
#include "rig.hpp"

namespace hapticd::eval {

struct OperatorLoad {
  std::string id;                       // "loose-grasp"
  std::string label;                    // "loose grasp, 5 N push"
  std::vector<std::string> attachment;  // the sim's attachment parameters
  std::vector<std::string> model;       // the virtual model's parameters the load needs (its wall)
  bool collision = false;               // judged by the operator's work, not by the velocity
};

// A virtual wall across `direction`, 1 cm ahead of where the handle starts, that the operator runs into.
struct WallSpec {
  double stiffness_n_per_m = 10000.0;
  double damping_n_s_per_m = 20.0;
};

// loose-grasp (grasp 0, a 5 N step of voluntary force along the direction at 0.2 s), firm-grasp (grasp 1, the
// same), voluntary-motion (grasp 0.5, the hand's target 4 cm along the direction and back, 0.5 Hz sine),
// wall-collision (loose grasp, the hand's target steps 3 cm along the direction at 0.2 s, into `wall`).
[[nodiscard]] std::vector<OperatorLoad> standard_loads(const Eigen::Vector3d& direction, const WallSpec& wall = {});
// The same loads in rotation about `axis` (world): firm-grasp and loose-grasp (a 0.2 N m step of voluntary
// torque at 0.2 s), voluntary-motion (grasp 0.5, the hand's target turns 0.1 rad about the axis and back, 0.5 Hz
// sine). No collision: the virtual admittance's walls are translational.
[[nodiscard]] std::vector<OperatorLoad> rotational_loads(const Eigen::Vector3d& axis);
// The collision with a given grasp (0 loose .. 1 firm): the Z-width's loads.
[[nodiscard]] OperatorLoad wall_collision(const Eigen::Vector3d& direction, double grasp, const WallSpec& wall);

struct StabilityCriterion {
  double duration_s = 2.0;
  double window_s = 0.5;
  double cutoff_hz = 4.0;
  double threshold_m_s = 0.02;
  double rotational_threshold_rad_s = 0.2;  // devices that render rotations
  double collision_tolerance_j = 0.01;
};

struct TrialResult {
  bool stable = false;
  double oscillation_m_s = 0.0;        // the RMS above the cutoff over the window
  double oscillation_rad_s = 0.0;      // the same of the angular velocity (devices that render rotations)
  double oscillation_hz = 0.0;         // its frequency (zero crossings of its largest axis, relative to threshold)
  double least_operator_work_j = 0.0;  // the minimum over time of the work the operator did on the handle
  std::string fault;                   // the device's, if it faulted
};

// The loads of `loads` whose id is in `ids`, in their order.
[[nodiscard]] std::vector<OperatorLoad> selected_loads(const std::vector<OperatorLoad>& loads,
                                                       const std::vector<std::string>& ids);
// For the result files: the loads (id, label) and the criterion's settings.
[[nodiscard]] Json loads_json(const std::vector<OperatorLoad>& loads);
[[nodiscard]] Json criterion_json(const StabilityCriterion& criterion);

// The rig under the load: its attachment and model lines added to the spec's.
[[nodiscard]] RigSpec with_load(RigSpec spec, const OperatorLoad& load);
// Runs the rig under the load and judges it.
[[nodiscard]] TrialResult run_trial(const RigSpec& spec, const OperatorLoad& load, const StabilityCriterion& criterion);

// Colgate's passivity experiment with the simulated operator: a firm grasp (the stiffest operator of the
// protocols) pushes and pulls the handle with a 10 N sine of voluntary force along `direction` at `frequency_hz`
// against a wall whose surface is where the handle starts (in contact half of each period); after two periods
// (and at least 0.3 s) the energy the handle port absorbs over whole periods (the true force of the hand on the
// handle times the true velocity), per period. Negative: the rendering gives out more energy than it takes at
// that frequency (not passive). (A stiff position source would test the same for impedance display, but an
// admittance display is active against any source that stiff, wall or no wall.)
struct PassivityResult {
  double energy_per_period_j = 0.0;
  std::string fault;
};
[[nodiscard]] PassivityResult port_energy(RigSpec spec, const Eigen::Vector3d& direction, const WallSpec& wall,
                                          double frequency_hz);

}  // namespace hapticd::eval
