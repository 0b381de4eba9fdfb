#include "resolved_acceleration.hpp"

#include <Eigen/Cholesky>

#include "hapticd/chain_state.hpp"

namespace hapticd::controllers {

ParameterSchema ResolvedAcceleration::parameter_schema() {
  ParameterSchema s;
  s.string("task", "controlled handle motion: auto (translation below 6 joints), translation, or full (6-D)")
      .choices({"auto", "translation", "full"}).default_value(std::string("auto"));
  s.real("bandwidth_rad_s", "translational loop bandwidth w: Kp = w^2, Kd = 2 zeta w").unit("rad/s").greater_than(0.0)
      .maximum(1000.0).default_value(60.0);
  s.real("rotational_bandwidth_rad_s", "rotational loop bandwidth").unit("rad/s").greater_than(0.0).maximum(1000.0)
      .default_value(40.0);
  s.real("damping_ratio", "zeta of both loops").greater_than(0.0).maximum(5.0).default_value(1.0);
  s.boolean("acceleration_feedforward", "add the desired acceleration").default_value(true);
  s.boolean("wrench_compensation", "cancel the measured operator wrench (positive feedback, + J^T F)").default_value(true);
  return s;
}

void ResolvedAcceleration::configure(const Parameters& p, const PluginContext& context) {
  if (context.device == nullptr || context.device->robot_model_file.empty()) {
    throw ParameterError("task", "resolved acceleration control needs a device with a robot model");
  }
  const std::string& task = p.string("task");
  rows_ = task == "full" ? 6 : task == "translation" ? 3 : (context.device->dof() >= 6 ? 6 : 3);
  if (rows_ > context.device->dof()) {
    throw ParameterError("task", "a 6-D task needs at least 6 joints; this device has " +
                                     std::to_string(context.device->dof()));
  }
  const double w = p.real("bandwidth_rad_s"), wr = p.real("rotational_bandwidth_rad_s"), z = p.real("damping_ratio");
  kp_ = w * w;
  kd_ = 2.0 * z * w;
  kp_rot_ = wr * wr;
  kd_rot_ = 2.0 * z * wr;
  acceleration_feedforward_ = p.boolean("acceleration_feedforward");
  wrench_compensation_ = p.boolean("wrench_compensation");
}

ReturnCode ResolvedAcceleration::activate(const ControllerInput& current, const JointCommand&) noexcept {
  return current.chain != nullptr && current.chain->model != nullptr ? ReturnCode::ok : ReturnCode::error;
}

ReturnCode ResolvedAcceleration::update(const CycleTime& /*cycle*/, const ControllerInput& in,
                                        JointCommand& command) noexcept {
  const ChainState& c = *in.chain;
  const model::ModelData& d = *c.data;
  const TaskTarget& t = in.task;
  if (!t.has_motion) return ReturnCode::error;

  model::Vector6d xdd = model::Vector6d::Zero();
  xdd.head<3>() = kp_ * (t.pose.position - c.handle_pose.position) + kd_ * (t.twist.linear - c.handle_twist.linear);
  if (rows_ == 6) {
    const Eigen::AngleAxisd error(t.pose.orientation * c.handle_pose.orientation.conjugate());
    xdd.tail<3>() = kp_rot_ * error.angle() * error.axis() + kd_rot_ * (t.twist.angular - c.handle_twist.angular);
  }
  if (acceleration_feedforward_) {
    xdd.head<3>() += t.acceleration.linear;
    xdd.tail<3>() += t.acceleration.angular;
  }
  xdd -= d.frame_jacobian_dot_qd;

  jacobian_ = d.frame_jacobian.topRows(rows_);
  // qdd = J^T (J J^T + l I)^-1 (xdd - dJ qd): the inverse for square J, minimum norm for redundant J.
  model::TaskMatrix jjt = jacobian_ * jacobian_.transpose();
  jjt.diagonal().array() += damping_;
  const model::TaskVector task_acceleration = xdd.head(rows_);
  const model::TaskVector weights = jjt.ldlt().solve(task_acceleration);
  JointVector qdd = JointVector::Zero(jacobian_.cols());
  qdd.noalias() = jacobian_.transpose() * weights;

  command.torque_nm.noalias() = d.mass_matrix * qdd;
  command.torque_nm += d.coriolis_torque + d.gravity_torque;
  if (wrench_compensation_ && c.has_operator_wrench) {
    model::Vector6d wrench;
    wrench << c.operator_wrench.force, c.operator_wrench.torque;
    command.torque_nm.noalias() -= jacobian_.transpose() * wrench.head(rows_);
  }
  return ReturnCode::ok;
}

}  // namespace hapticd::controllers
