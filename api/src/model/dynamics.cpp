#include "hapticd/model/dynamics.hpp"

#include "hapticd/model/kinematics.hpp"

namespace hapticd::model {
namespace {

void update_composites(const RobotModel& model, ModelData& data) noexcept {
  SpatialInertia sum;
  for (int i = model.dof() - 1; i >= 0; --i) {
    sum += data.inertia[i];
    data.composite[i] = sum;
  }
}

// Base acceleration that accounts for gravity in the Newton-Euler recursion (Featherstone's trick).
Motion gravity_base_acceleration(const RobotModel& model) noexcept {
  return {Eigen::Vector3d::Zero(), -model.gravity()};
}

// tau = sum over the chain of S_i^T f_i for body accelerations a_i = base + bias_i + sum_{j<=i} S_j qdd_j.
// qdd == nullptr: qdd = 0.
void newton_euler(const RobotModel& model, ModelData& data, const Motion& base, const JointVector* qdd,
                  bool with_velocity, JointVector& tau) noexcept {
  const int n = model.dof();
  Motion a = base;
  Motion a_qdd;  // sum of S_j qdd_j
  for (int i = 0; i < n; ++i) {
    if (qdd != nullptr) a_qdd += data.motion_subspace[i] * (*qdd)[i];
    Motion ai = a + a_qdd;
    if (with_velocity) ai += data.bias_acceleration[i];
    Force f = data.inertia[i] * ai;
    if (with_velocity) {
      const Motion& v = data.velocity[i];
      f += cross(v, data.inertia[i] * v);
    }
    data.force[i] = f;
  }
  Force sum;
  for (int i = n - 1; i >= 0; --i) {
    sum += data.force[i];
    tau[i] = dot(data.motion_subspace[i], sum);
    if (qdd != nullptr) tau[i] += model.body(i).reflected_inertia * (*qdd)[i];
  }
}

}  // namespace

void joint_space_inertia(const RobotModel& model, ModelData& data) noexcept {
  const int n = model.dof();
  update_composites(model, data);
  for (int j = 0; j < n; ++j) data.composite_subspace[j] = data.composite[j] * data.motion_subspace[j];
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i <= j; ++i) {
      const double m = dot(data.motion_subspace[i], data.composite_subspace[j]);
      data.mass_matrix(i, j) = m;
      data.mass_matrix(j, i) = m;
    }
    data.mass_matrix(j, j) += model.body(j).reflected_inertia;
  }
  data.mass_llt.compute(data.mass_matrix);
}

void gravity_torques(const RobotModel& model, ModelData& data) noexcept {
  update_composites(model, data);
  const Motion a0 = gravity_base_acceleration(model);
  for (int i = 0; i < model.dof(); ++i) {
    data.gravity_torque[i] = dot(data.motion_subspace[i], data.composite[i] * a0);
  }
}

void coriolis_torques(const RobotModel& model, ModelData& data) noexcept {
  newton_euler(model, data, Motion{}, nullptr, true, data.coriolis_torque);
}

void coriolis_matrix(const RobotModel& model, ModelData& data, JointMatrix& coriolis) noexcept {
  // C = sum_i J_i^T (I_i dJ_i/dt + (v_i x*) I_i J_i), J_i = [S_0 .. S_i 0 ..]: column j of body i's term is
  // g_ij = I_i dS_j/dt + v_i x* (I_i S_j) for j <= i, and C(k, j) = S_k^T sum_{i >= max(k, j)} g_ij.
  const int n = model.dof();
  coriolis.setZero(n, n);
  for (int j = 0; j < n; ++j) {
    Force sum;
    for (int i = n - 1; i >= 0; --i) {
      if (i >= j) {
        const SpatialInertia& inertia = data.inertia[i];
        sum += inertia * data.subspace_rate[j] + cross(data.velocity[i], inertia * data.motion_subspace[j]);
      }
      // For k = i: max(k, j) = max(i, j); sum now holds the terms of bodies >= max(i, j).
      coriolis(i, j) = dot(data.motion_subspace[i], sum);
    }
  }
}

void inverse_dynamics(const RobotModel& model, ModelData& data, const JointVector& qdd, JointVector& tau) noexcept {
  newton_euler(model, data, gravity_base_acceleration(model), &qdd, true, tau);
}

void forward_dynamics(const RobotModel& model, ModelData& data, const JointVector& tau, JointVector& qdd) noexcept {
  joint_space_inertia(model, data);
  newton_euler(model, data, gravity_base_acceleration(model), nullptr, true, data.scratch);
  qdd = tau - data.scratch;
  data.mass_llt.solveInPlace(qdd);
}

void compute_cycle_terms(const RobotModel& model, ModelData& data, const JointVector& q, const JointVector& qd,
                         int frame_id) noexcept {
  forward_velocity(model, data, q, qd);
  data.frame_pose = frame_pose(model, data, frame_id);
  frame_jacobian(model, data, frame_id, data.frame_jacobian);
  data.frame_jacobian_dot_qd = frame_jacobian_dot_times_qd(model, data, frame_id);
  joint_space_inertia(model, data);  // also the composite inertias used by gravity_torques
  const Motion a0 = gravity_base_acceleration(model);
  for (int i = 0; i < model.dof(); ++i) {
    data.gravity_torque[i] = dot(data.motion_subspace[i], data.composite[i] * a0);
  }
  coriolis_torques(model, data);
}

}  // namespace hapticd::model
