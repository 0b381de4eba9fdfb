#pragma once
// The robot model of a rig's device, for what the experiments compute from the model rather than measure: the
// joint configuration that puts the handle at a point (the tracking path's start, the transparency grid), and
// the handle's task-space inertia there (Table 5.1's indices).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "hapticd/model/model_data.hpp"
#include "hapticd/model/robot_model.hpp"

namespace hapticd::eval {

class DeviceModel {
 public:
  explicit DeviceModel(const std::string& device);  // a shipped device's name (device_presets.hpp)

  // Joints that put the handle at `position` (orientation free), from the preset's seed; throws
  // std::runtime_error when the point is out of reach.
  [[nodiscard]] std::vector<double> joints_at(const Eigen::Vector3d& position);
  [[nodiscard]] Eigen::Vector3d handle_at(const std::vector<double>& joints);
  // The handle's orientation (its axes in world coordinates, columns).
  [[nodiscard]] Eigen::Matrix3d handle_rotation_at(const std::vector<double>& joints);

  // At a configuration: the translational rows of the handle Jacobian (3 x n), the joint-space inertia M and the
  // handle's task-space inertia Lambda = (J M^-1 J^T)^-1 (3 x 3, the apparent mass of the open-loop device).
  struct Inertia {
    Eigen::MatrixXd jacobian;
    Eigen::MatrixXd joint_inertia;
    Eigen::Matrix3d task_inertia;
  };
  [[nodiscard]] Inertia inertia_at(const std::vector<double>& joints);

  [[nodiscard]] const model::RobotModel& robot() const noexcept { return robot_; }

 private:
  std::string device_;
  model::RobotModel robot_;
  model::ModelData data_;
  int frame_ = -1;
};

}  // namespace hapticd::eval
