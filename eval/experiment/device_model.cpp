#include "device_model.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "device_presets.hpp"
#include "hapticd/model/dynamics.hpp"
#include "hapticd/model/kinematics.hpp"
#include "hapticd/model/position_solver.hpp"
#include "hapticd/model/urdf_loader.hpp"

namespace hapticd::eval {

DeviceModel::DeviceModel(const std::string& device)
    : device_(device),
      robot_(model::load_robot_model(find_device_urdf(device))),
      data_(robot_),
      frame_(robot_.require_frame("handle")) {}

std::vector<double> DeviceModel::joints_at(const Eigen::Vector3d& position) {
  const DevicePreset preset = device_preset(device_);
  JointVector q(robot_.dof());
  for (int i = 0; i < robot_.dof(); ++i) q[i] = preset.seed[static_cast<std::size_t>(i)];
  model::forward_kinematics(robot_, data_, q);
  Eigen::Isometry3d target = model::frame_pose(robot_, data_, frame_);
  target.translation() = position;
  model::PositionSolverOptions options;
  options.rows = preset.task;
  const model::PositionSolution s = model::solve_position(robot_, data_, frame_, target, q, options);
  if (!s.converged || s.error > 1e-6) {
    throw std::runtime_error(fmt::format("the {} handle cannot reach ({:.3f}, {:.3f}, {:.3f}) m", device_, position.x(),
                                         position.y(), position.z()));
  }
  return {q.data(), q.data() + q.size()};
}

Eigen::Vector3d DeviceModel::handle_at(const std::vector<double>& joints) {
  const JointVector q = Eigen::Map<const Eigen::VectorXd>(joints.data(), static_cast<Eigen::Index>(joints.size()));
  model::forward_kinematics(robot_, data_, q);
  return model::frame_pose(robot_, data_, frame_).translation();
}

Eigen::Matrix3d DeviceModel::handle_rotation_at(const std::vector<double>& joints) {
  const JointVector q = Eigen::Map<const Eigen::VectorXd>(joints.data(), static_cast<Eigen::Index>(joints.size()));
  model::forward_kinematics(robot_, data_, q);
  return model::frame_pose(robot_, data_, frame_).linear();
}

DeviceModel::Inertia DeviceModel::inertia_at(const std::vector<double>& joints) {
  const JointVector q = Eigen::Map<const Eigen::VectorXd>(joints.data(), static_cast<Eigen::Index>(joints.size()));
  const JointVector qd = JointVector::Zero(robot_.dof());
  model::compute_cycle_terms(robot_, data_, q, qd, frame_);
  Inertia r;
  r.jacobian = data_.frame_jacobian.topRows(3);
  r.joint_inertia = data_.mass_matrix;
  const Eigen::MatrixXd minv_jt = data_.mass_llt.solve(r.jacobian.transpose());
  r.task_inertia = (r.jacobian * minv_jt).inverse();
  return r;
}

}  // namespace hapticd::eval
