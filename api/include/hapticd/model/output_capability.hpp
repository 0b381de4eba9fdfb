#pragma once
// Output capability of a haptic device (the thesis's appendix C): at a configuration, the largest force,
// velocity and acceleration the handle can produce in its worst direction, within the joint torque and
// speed limits. See docs/output-capability.md for the definitions and the results for the ViSHaRD devices.
//
// All three sets are polytopes {x : |a_i^T x + b_i| <= l_i} in the chosen 3-D subspace, so the worst
// direction value is exactly the radius of the largest centred ball inside: min_i (l_i - |b_i|) / |a_i|.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "hapticd/export.hpp"
#include "hapticd/model/model_data.hpp"
#include "hapticd/model/task_space.hpp"

namespace hapticd::model {

// Which handle quantity is evaluated: forces, velocities and accelerations (translation), or torques,
// angular velocities and angular accelerations (rotation). The other subspace is held at zero (pure force
// with zero torque, translation without rotation, and vice versa).
enum class CapabilitySubspace { translation, rotation };

struct CapabilityOptions {
  TaskRows task = TaskRows::full;  // rows the device controls (kTranslation for ViSHaRD3)
  CapabilitySubspace subspace = CapabilitySubspace::translation;
  bool include_gravity = true;  // the torque spent on holding the arm is not available
};

struct WorstDirection {
  double value = 0.0;                                    // [N, m/s, m/s^2] or [N m, rad/s, rad/s^2]
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  // a worst direction (world axes, either sign)
  int limiting_joint = -1;
};

struct PoseCapability {
  WorstDirection force;         // or torque
  WorstDirection velocity;      // from the pseudoinverse (minimum-norm) joint velocity
  WorstDirection acceleration;  // from rest, pseudoinverse joint acceleration
  double task_condition = 0.0;  // condition number of the task Jacobian
};

// Evaluates at q (runs forward kinematics, M and g on `data`). Limits default to the model's drive data.
[[nodiscard]] HAPTICD_API PoseCapability output_capability(const RobotModel& model, ModelData& data,
                                                           const JointVector& q, int frame_id,
                                                           const CapabilityOptions& options);
[[nodiscard]] HAPTICD_API PoseCapability output_capability(const RobotModel& model, ModelData& data,
                                                           const JointVector& q, int frame_id,
                                                           const CapabilityOptions& options,
                                                           const JointVector& torque_limits,
                                                           const JointVector& speed_limits);

// A grid of handle poses: positions on a box (points_per_axis^3, centred), times orientations given as
// rotations about the world axes, Rz(yaw) Ry(pitch) Rx(roll), applied to the nominal handle orientation.
struct WorkspaceGrid {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d size = Eigen::Vector3d::Zero();  // full edge lengths [m]
  int points_per_axis = 5;
  Eigen::Matrix3d nominal_orientation = Eigen::Matrix3d::Identity();
  std::vector<Eigen::Vector3d> orientation_offsets{Eigen::Vector3d::Zero()};  // rpy [rad]
  // true: only positions are targets; the orientation is what the solver's continuation from the seed gives
  // (for devices whose orientation and position are coupled, such as ViSHaRD6's pitch and height).
  bool free_orientation = false;
};

struct GridCapability {
  int poses = 0;
  int reached = 0;                               // poses the position solver reached
  WorstDirection force, velocity, acceleration;  // minima over the reached poses
  Eigen::Vector3d force_worst_position, velocity_worst_position, acceleration_worst_position;
  double mean_force = 0.0, mean_velocity = 0.0, mean_acceleration = 0.0;
  double worst_condition = 0.0;
};

// Worst case over the grid. q_seed is the solver's start for the first pose; each pose starts from the
// nearest solved neighbour. Not real-time (an off-line analysis).
[[nodiscard]] HAPTICD_API GridCapability grid_output_capability(const RobotModel& model, int frame_id,
                                                                const WorkspaceGrid& grid, const JointVector& q_seed,
                                                                const CapabilityOptions& options);

}  // namespace hapticd::model
