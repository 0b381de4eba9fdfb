#include "spring_link_group_model.hpp"

namespace example {

hapticd::ParameterSchema SpringLinkGroupModel::parameter_schema() {
  hapticd::ParameterSchema s;
  s.real("rest_length_m", "the spring's length without force").unit("m").minimum(0.0).default_value(0.2);
  s.real("stiffness_n_per_m", "the spring").unit("N/m").minimum(0.0).maximum(5000.0).default_value(100.0).tunable();
  s.real("damping_n_s_per_m", "along the line").unit("N s/m").minimum(0.0).default_value(2.0);
  return s;
}

void SpringLinkGroupModel::configure(const hapticd::Parameters& p, const hapticd::GroupModelContext& context) {
  if (context.devices.size() < 2)
    throw hapticd::ParameterError("", "a spring link needs a group of two devices, '" + context.group_name + "' has " +
                                          std::to_string(context.devices.size()));
  rest_m_ = p.real("rest_length_m");
  damping_ = p.real("damping_n_s_per_m");
  tune(p);
}

void SpringLinkGroupModel::tune(const hapticd::Parameters& p) { stiffness_ = p.real("stiffness_n_per_m"); }

hapticd::Outcome SpringLinkGroupModel::activate(std::span<const hapticd::GroupHand> hands) {
  return hands.size() >= 2 ? hapticd::Outcome::success() : hapticd::Outcome::failure("a spring link needs two hands");
}

hapticd::Outcome SpringLinkGroupModel::update(const hapticd::CycleTime&, std::span<const hapticd::GroupHand> hands,
                                              std::span<Eigen::Vector3d> handle_force) {
  if (hands.size() < 2 || handle_force.size() != hands.size())
    return hapticd::Outcome::failure("a spring link needs two hands");
  for (Eigen::Vector3d& f : handle_force) f.setZero();
  const Eigen::Vector3d d = hands[1].pose.position - hands[0].pose.position;
  const double length = d.norm();
  if (length < 1e-9) return hapticd::Outcome::success();  // no direction: no force
  const Eigen::Vector3d u = d / length;
  const double stretch_rate = (hands[1].twist.linear - hands[0].twist.linear).dot(u);
  const double tension = stiffness_.load(std::memory_order_relaxed) * (length - rest_m_) + damping_ * stretch_rate;
  handle_force[0] = tension * u;  // pulls the first hand towards the second when stretched
  handle_force[1] = -tension * u;
  return hapticd::Outcome::success();
}

}  // namespace example
