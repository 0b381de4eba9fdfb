#pragma once
// Task-space measures from a Jacobian: operational-space inertia, manipulability, condition number.
// Real-time safe (fixed-capacity Eigen storage only).
#include <string>

#include "hapticd/chain_state.hpp"
#include "hapticd/export.hpp"
#include "hapticd/model/model_data.hpp"
#include "hapticd/parameters.hpp"

namespace hapticd::model {

// Which rows of a [linear; angular] frame Jacobian a task uses.
enum class TaskRows { full, translation, rotation };

// The selected rows of a 6 x n Jacobian.
HAPTICD_API void select_rows(const TaskJacobian& full, TaskRows rows, TaskJacobian& task) noexcept;

// Operational-space inertia Lambda = (J M^-1 J^T)^-1 for an m x n task Jacobian (m <= 6). Requires
// joint_space_inertia. Returns false when J M^-1 J^T is singular (task rank below m).
HAPTICD_API bool operational_space_inertia(const ModelData& data, const TaskJacobian& jacobian,
                                           TaskMatrix& lambda) noexcept;
// Yoshikawa's manipulability sqrt(det(J J^T)) (m <= n).
[[nodiscard]] HAPTICD_API double manipulability(const TaskJacobian& jacobian) noexcept;
// sigma_max / sigma_min of J (infinity when rank-deficient). Mixed linear/angular rows should be scaled
// by a characteristic length by the caller.
[[nodiscard]] HAPTICD_API double condition_number(const TaskJacobian& jacobian) noexcept;

// The minimum-norm joint vector q with J q = v (exact for full row rank), through the damped normal equations
// q = J^T (J J^T + damping I)^-1 v; a small damping keeps it bounded at singularities. Real-time safe.
[[nodiscard]] HAPTICD_API JointVector minimum_norm_solution(const TaskJacobian& jacobian, const TaskVector& v,
                                                            double damping = 1e-6) noexcept;
// J_rows^T w_rows over the first `rows` rows of a [linear; angular] frame Jacobian: the joint torques of a
// handle wrench (rows 3: force only). Real-time safe.
[[nodiscard]] HAPTICD_API JointVector jacobian_transpose_times(const TaskJacobian& jacobian, int rows,
                                                               const Vector6d& wrench) noexcept;

// The "task" parameter shared by the task-space plugins: auto (translation below 6 joints), translation or
// full (6-D). declare_task_parameter adds it to a schema; task_rows turns the choice into 3 or 6 rows and
// throws ParameterError("task") when 6 rows are asked of a device with fewer joints. Not real-time safe.
HAPTICD_API void declare_task_parameter(ParameterSchema& schema, const std::string& description);
[[nodiscard]] HAPTICD_API int task_rows(const std::string& choice, int dof);

// J^T F_h over the task rows: the joint torques of the operator's measured wrench (zero without a sensor).
// Real-time safe.
[[nodiscard]] HAPTICD_API JointVector operator_wrench_torques(const ChainState& chain, int rows) noexcept;

}  // namespace hapticd::model
