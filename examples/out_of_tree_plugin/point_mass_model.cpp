#include "point_mass_model.hpp"

namespace example {

hapticd::ParameterSchema PointMassModel::parameter_schema() {
  hapticd::ParameterSchema s;
  s.real("mass_kg", "the virtual mass").unit("kg").greater_than(0.0).default_value(2.0);
  s.real("damping_n_s_per_m", "the virtual viscous damping").unit("N s/m").minimum(0.0).default_value(5.0);
  return s;
}

void PointMassModel::configure(const hapticd::Parameters& p, const hapticd::PluginContext&) {
  mass_kg_ = p.real("mass_kg");
  damping_ = p.real("damping_n_s_per_m");
}

hapticd::Outcome PointMassModel::activate(const hapticd::VirtualModelInput& current) {
  position_ = current.chain.handle_pose.position;  // start where the handle is: no jump at the hand-over
  velocity_ = current.chain.handle_twist.linear;
  return hapticd::Outcome::success();
}

hapticd::Outcome PointMassModel::update(const hapticd::CycleTime& cycle, const hapticd::VirtualModelInput& in,
                                        hapticd::TaskTarget& target) {
  const double dt = static_cast<double>(cycle.period_ns) * 1e-9;
  // No environment of its own here; one would go through in.render.limit() first.
  const Eigen::Vector3d force = in.chain.operator_wrench.force + in.render.take_safety_force() - damping_ * velocity_;
  const Eigen::Vector3d acceleration = force / mass_kg_;
  velocity_ += acceleration * dt;  // semi-implicit Euler
  position_ += velocity_ * dt;
  target.pose.position = position_;
  target.pose.orientation = in.chain.handle_pose.orientation;
  target.twist.linear = velocity_;
  target.twist.angular.setZero();
  target.acceleration.linear = acceleration;
  target.acceleration.angular.setZero();
  target.has_motion = true;
  target.has_wrench = false;
  return position_.allFinite() ? hapticd::Outcome::success()
                               : hapticd::Outcome::failure("the point mass left the finite numbers");
}

}  // namespace example
