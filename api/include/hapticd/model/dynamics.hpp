#pragma once
// Rigid-body dynamics of a RobotModel, M(q) qdd + C(q, qd) qd + g(q) = tau, with the reflected drive
// inertia on M's diagonal (rotor gyroscopic coupling neglected). Real-time safe once ModelData exists.
// Each function states what it requires to have run on the same ModelData at the same q (and qd).
#include "hapticd/export.hpp"
#include "hapticd/model/model_data.hpp"

namespace hapticd::model {

// data.mass_matrix and its Cholesky factor data.mass_llt (composite-rigid-body algorithm).
// Requires forward_kinematics.
HAPTICD_API void joint_space_inertia(const RobotModel& model, ModelData& data) noexcept;
// data.gravity_torque. Requires forward_kinematics.
HAPTICD_API void gravity_torques(const RobotModel& model, ModelData& data) noexcept;
// data.coriolis_torque = C(q, qd) qd. Requires forward_velocity.
HAPTICD_API void coriolis_torques(const RobotModel& model, ModelData& data) noexcept;
// The Coriolis matrix C(q, qd) with dM/dt - 2C skew-symmetric. Requires forward_velocity.
HAPTICD_API void coriolis_matrix(const RobotModel& model, ModelData& data, JointMatrix& coriolis) noexcept;
// tau = M qdd + C qd + g (recursive Newton-Euler). Requires forward_velocity.
HAPTICD_API void inverse_dynamics(const RobotModel& model, ModelData& data, const JointVector& qdd,
                                  JointVector& tau) noexcept;
// qdd = M^-1 (tau - C qd - g). Requires forward_velocity; computes M, C qd and g itself.
HAPTICD_API void forward_dynamics(const RobotModel& model, ModelData& data, const JointVector& tau,
                                  JointVector& qdd) noexcept;

// The per-cycle set a control chain needs, computed once with shared work: forward_velocity, the pose,
// Jacobian and dJ/dt qd of `frame_id`, M (with Cholesky), C qd and g, all into `data`.
HAPTICD_API void compute_cycle_terms(const RobotModel& model, ModelData& data, const JointVector& q,
                                     const JointVector& qd, int frame_id) noexcept;

}  // namespace hapticd::model
