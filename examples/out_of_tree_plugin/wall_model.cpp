#include "wall_model.hpp"

namespace example {

hapticd::ParameterSchema WallModel::parameter_schema() {
  hapticd::ParameterSchema s;
  s.real("height_m", "the wall's plane, world z; the handle is pushed up above it").unit("m").default_value(0.0);
  s.real("stiffness_n_per_m", "the wall's spring").unit("N/m").greater_than(0.0).default_value(2000.0);
  s.real("damping_n_s_per_m", "the wall's damper, while the handle is in the wall")
      .unit("N s/m")
      .minimum(0.0)
      .default_value(5.0);
  return s;
}

void WallModel::configure(const hapticd::Parameters& p, const hapticd::PluginContext&) {
  height_m_ = p.real("height_m");
  stiffness_ = p.real("stiffness_n_per_m");
  damping_ = p.real("damping_n_s_per_m");
}

hapticd::Outcome WallModel::activate(const hapticd::VirtualModelInput&) { return hapticd::Outcome::success(); }

hapticd::Outcome WallModel::update(const hapticd::CycleTime&, const hapticd::VirtualModelInput& in,
                                   hapticd::TaskTarget& target) {
  const double depth = height_m_ - in.chain.handle_pose.position.z();
  hapticd::RenderPort::Vector6 wrench = hapticd::RenderPort::Vector6::Zero();
  if (depth > 0.0) wrench[2] = stiffness_ * depth - damping_ * in.chain.handle_twist.linear.z();
  wrench = in.render.limit(wrench);  // the safety layer's limits; the port records that this model applied them
  target.wrench.force = wrench.head<3>();
  target.wrench.torque = wrench.tail<3>();
  target.has_wrench = true;
  target.has_motion = false;
  return hapticd::Outcome::success();
}

}  // namespace example
