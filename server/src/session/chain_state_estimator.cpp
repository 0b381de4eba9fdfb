#include "session/chain_state_estimator.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "hapticd/model/dynamics.hpp"
#include "hapticd/model/kinematics.hpp"
#include "hapticd/model/urdf_loader.hpp"

namespace hapticd::server {

ChainStateEstimator::ChainStateEstimator(const DeviceDescription& description,
                                         std::shared_ptr<const model::RobotModel> robot, double period_s)
    : measures_velocity_(description.reports_joint_velocity),
      handle_device_(description.interface == DeviceInterface::handle),
      handle_(description.handle),
      base_(to_isometry(description.base_pose)),
      robot_(std::move(robot)) {
  differentiator_.configure(period_s, kVelocityFilterHz);
  if (robot_ == nullptr) return;
  model_data_ = std::make_unique<model::ModelData>(*robot_);
  state_.model = robot_.get();
  state_.data = model_data_.get();
  state_.handle_frame = robot_->require_frame(description.handle_frame.empty() ? "handle" : description.handle_frame);
  if (description.reports_wrench && !description.sensor_frame.empty())
    sensor_frame_ = robot_->require_frame(description.sensor_frame);
}

void ChainStateEstimator::estimate(DeviceState& measured, std::int64_t time_ns, std::int64_t period_ns,
                                   bool restart) noexcept {
  ChainState& c = state_;
  if (handle_device_) {
    // The axes from the handle (base frame); the handle in the world for the chain.
    const HandleState& h = measured.handle;
    handle_to_axes(handle_, h, measured.joints.position, measured.joints.velocity);
    c.handle_pose.position = base_ * h.pose.position;
    c.handle_pose.orientation = Eigen::Quaterniond(base_.linear()) * h.pose.orientation.normalized();
    c.handle_twist.linear = base_.linear() * h.twist.linear;
    c.handle_twist.angular = base_.linear() * h.twist.angular;
    c.has_handle = true;
    differentiated_ns_ = time_ns;
    ready_ = true;
    return;
  }
  JointVector& qd = measured.joints.velocity;  // a device that measures velocity: its measurement stays
  if (measures_velocity_) {
    // nothing to estimate
  } else if (restart || !ready_) {
    differentiator_.reset(measured.joints.position);
    qd.setZero(measured.joints.position.size());
  } else {
    // After skipped periods (an overloaded real-time loop) the difference spans the time that really passed.
    const std::int64_t elapsed_ns = std::max<std::int64_t>(period_ns, time_ns - differentiated_ns_);
    qd = differentiator_.update(measured.joints.position, static_cast<double>(elapsed_ns) * 1e-9);
  }
  differentiated_ns_ = time_ns;
  ready_ = true;
  if (robot_ == nullptr) return;
  model::compute_cycle_terms(*robot_, *model_data_, measured.joints.position, qd, c.handle_frame);
  const model::ModelData& d = *model_data_;
  c.handle_pose.position = d.frame_pose.translation();
  c.handle_pose.orientation = Eigen::Quaterniond(d.frame_pose.linear());
  const model::Vector6d twist = d.frame_jacobian * qd;
  c.handle_twist.linear = twist.head<3>();
  c.handle_twist.angular = twist.tail<3>();
  c.has_handle = true;
  if (sensor_frame_ >= 0) {
    // The sensor's wrench, turned into the world, less the weight of what the sensor carries (the model's
    // links beyond the sensor frame: handle, gimbal), moved to the handle point. The carried mass's inertial
    // force stays in the estimate: the operator feels it as part of the device.
    const Eigen::Isometry3d sensor = model::frame_pose(*robot_, d, sensor_frame_);
    const model::Frame& carried = robot_->frame(sensor_frame_);
    const Eigen::Vector3d weight = carried.carried_mass * robot_->gravity();
    const Eigen::Vector3d force = sensor.linear() * measured.sensor_wrench.force - weight;
    const Eigen::Vector3d moment =
        sensor.linear() * measured.sensor_wrench.torque - (sensor.linear() * carried.carried_com).cross(weight);
    c.operator_wrench.force = force;
    c.operator_wrench.torque = moment + (sensor.translation() - c.handle_pose.position).cross(force);
    c.has_operator_wrench = true;
  }
}

}  // namespace hapticd::server
