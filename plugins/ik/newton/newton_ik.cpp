#include "newton_ik.hpp"

#include "hapticd/chain_state.hpp"
#include "hapticd/model/kinematics.hpp"
#include "hapticd/model/task_space.hpp"
#include "hapticd/model/urdf_loader.hpp"

namespace hapticd::ik {

ParameterSchema NewtonIk::parameter_schema() {
  ParameterSchema s;
  model::declare_task_parameter(s, "task rows");
  s.integer("newton_steps", "Newton steps per cycle").minimum(1).maximum(10).default_value(1);
  s.real("acceleration_filter_hz", "low-pass of the differentiated joint-velocity target")
      .unit("Hz")
      .greater_than(0.0)
      .default_value(200.0);
  return s;
}

void NewtonIk::configure(const Parameters& p, const PluginContext& context) {
  if (context.device == nullptr || context.robot_model == nullptr) {
    throw ParameterError("task", "the Newton inverse kinematics needs a device with a robot model");
  }
  model_ = context.robot_model;
  data_ = std::make_unique<model::ModelData>(*model_);
  handle_ = model_->require_frame(context.device->handle_frame.empty() ? "handle" : context.device->handle_frame);
  rows_ = model::task_rows(p.string("task"), model_->dof());
  steps_ = static_cast<int>(p.integer("newton_steps"));
  acceleration_.configure(1.0 / context.rate_hz, p.real("acceleration_filter_hz"));
  q_.setZero(model_->dof());
  qd_.setZero(model_->dof());
}

Outcome NewtonIk::activate(const InverseKinematicsInput& current) {
  q_ = current.device.joints.position;
  qd_ = current.device.joints.velocity;
  acceleration_.reset(qd_);
  return Outcome::success();
}

Outcome NewtonIk::update(const CycleTime& /*cycle*/, const InverseKinematicsInput& in, JointTarget& target) {
  if (!in.task.has_motion)
    return Outcome::failure("no desired motion: the scheme needs an admittance-type virtual model");
  Eigen::Isometry3d desired = Eigen::Isometry3d::Identity();
  desired.translation() = in.task.pose.position;
  desired.linear() = in.task.pose.orientation.toRotationMatrix();
  for (int s = 0; s < steps_; ++s) {
    model::forward_kinematics(*model_, *data_, q_, model::BodyInertias::skip);
    model::frame_jacobian(*model_, *data_, handle_, jacobian_);
    const model::TaskJacobian j = jacobian_.topRows(rows_);
    const model::Vector6d error = model::pose_difference(desired, model::frame_pose(*model_, *data_, handle_));
    q_ += model::minimum_norm_solution(j, model::TaskVector(error.head(rows_)), damping_);
  }
  model::forward_kinematics(*model_, *data_, q_, model::BodyInertias::skip);
  model::frame_jacobian(*model_, *data_, handle_, jacobian_);
  const model::TaskJacobian j = jacobian_.topRows(rows_);
  model::Vector6d twist;
  twist << in.task.twist.linear, in.task.twist.angular;
  qd_ = model::minimum_norm_solution(j, model::TaskVector(twist.head(rows_)), damping_);
  target.position = q_;
  target.velocity = qd_;
  target.acceleration = acceleration_.update(qd_);
  target.valid = true;
  return Outcome::success();
}

}  // namespace hapticd::ik
