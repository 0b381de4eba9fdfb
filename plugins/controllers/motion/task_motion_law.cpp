#include "task_motion_law.hpp"

#include "hapticd/model/task_space.hpp"

namespace hapticd::controllers {

void TaskMotionLaw::declare(ParameterSchema& s) {
  model::declare_task_parameter(s, "controlled handle motion");
  s.real("bandwidth_rad_s", "translational loop bandwidth w: Kp = w^2, Kd = 2 zeta w")
      .unit("rad/s")
      .greater_than(0.0)
      .maximum(1000.0)
      .default_value(60.0)
      .tunable();
  s.real("rotational_bandwidth_rad_s", "rotational loop bandwidth")
      .unit("rad/s")
      .greater_than(0.0)
      .maximum(1000.0)
      .default_value(40.0)
      .tunable();
  s.real("damping_ratio", "zeta of both loops").greater_than(0.0).maximum(5.0).default_value(1.0).tunable();
  s.boolean("acceleration_feedforward", "add the desired acceleration").default_value(true);
  s.boolean("wrench_compensation", "cancel the measured operator wrench (positive feedback, + J^T F)")
      .default_value(true);
}

void TaskMotionLaw::configure(const Parameters& p, const PluginContext& context) {
  if (context.device == nullptr || context.device->robot_model_file.empty()) {
    throw ParameterError("task", "admittance control needs a device with a robot model");
  }
  rows_ = model::task_rows(p.string("task"), context.device->dof());
  apply(gains_of(p));
  acceleration_feedforward_ = p.boolean("acceleration_feedforward");
  wrench_compensation_ = p.boolean("wrench_compensation");
}

TaskMotionLaw::Gains TaskMotionLaw::gains_of(const Parameters& p) {
  const double w = p.real("bandwidth_rad_s"), wr = p.real("rotational_bandwidth_rad_s"), z = p.real("damping_ratio");
  return {w * w, 2.0 * z * w, wr * wr, 2.0 * z * wr};
}

void TaskMotionLaw::apply(const Gains& g) noexcept {
  kp_ = g.kp;
  kd_ = g.kd;
  kp_rot_ = g.kp_rot;
  kd_rot_ = g.kd_rot;
}

void TaskMotionLaw::tune(const Parameters& p) { inbox_.publish(gains_of(p)); }

void TaskMotionLaw::take_tuned() noexcept {
  if (inbox_.take(incoming_)) apply(incoming_);
}

model::Vector6d TaskMotionLaw::acceleration(const TaskTarget& t, const ChainState& c) const noexcept {
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
  return xdd;
}

void TaskMotionLaw::add_wrench_compensation(const ChainState& c, JointVector& torque) const noexcept {
  if (wrench_compensation_) torque -= model::operator_wrench_torques(c, rows_);
}

}  // namespace hapticd::controllers
