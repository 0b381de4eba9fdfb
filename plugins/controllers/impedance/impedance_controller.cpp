#include "impedance_controller.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hapticd/chain_state.hpp"
#include "hapticd/model/task_space.hpp"

namespace hapticd::controllers {

ParameterSchema ImpedanceController::parameter_schema() {
  ParameterSchema s;
  model::declare_task_parameter(s, "rendered handle wrench");
  s.real("force_gain", "proportional force feedback Kp (0: open-loop impedance control)").minimum(0.0).maximum(50.0)
      .default_value(0.0);
  s.real("force_derivative_gain", "derivative force feedback Kd").unit("s").minimum(0.0).maximum(1.0).default_value(0.0);
  s.real("derivative_filter_hz", "low-pass of the force-error derivative").unit("Hz").greater_than(0.0)
      .default_value(100.0);
  s.boolean("gravity_compensation", "add the model's gravity torques").default_value(true);
  s.boolean("friction_compensation", "add the model's sliding friction in the direction of motion").default_value(false);
  s.real_vector("friction_polynomial", "p0 .. p4 of the sliding friction [N m vs rad/s] (default: the 26 C curve)")
      .size(5).default_value(std::vector<double>{1.183, 1.008, -0.2642, 0.0487, -0.0037});
  s.real_vector("friction_load", "a0, a1, a2 of the load-dependent friction").size(3)
      .default_value(std::vector<double>{0.0, 0.02, 0.0});
  s.real("friction_velocity_max", "highest identified velocity: the polynomial is held beyond it").unit("rad/s")
      .greater_than(0.0).default_value(5.0);
  s.real("friction_smooth_velocity", "velocity over which the compensation direction blends in").unit("rad/s")
      .greater_than(0.0).default_value(0.05);
  s.real("friction_fraction", "share of the modelled friction compensated").minimum(0.0).maximum(1.0)
      .default_value(0.8);
  s.real("notch_hz", "centre of the torque notch filters (the joint resonance); 0: off").unit("Hz").minimum(0.0)
      .default_value(0.0);
  s.integer("notch_sections", "notch sections in series").minimum(1).maximum(4).default_value(2);
  s.real("notch_zeta_numerator", "damping ratio of the notch zeros (depth = numerator / denominator)").minimum(0.0)
      .default_value(0.01);
  s.real("notch_zeta_denominator", "damping ratio of the notch poles (width)").greater_than(0.0).default_value(0.2);
  return s;
}

void ImpedanceController::configure(const Parameters& p, const PluginContext& context) {
  if (context.device == nullptr || context.device->robot_model_file.empty()) {
    throw ParameterError("task", "impedance control needs a device with a robot model");
  }
  rows_ = model::task_rows(p.string("task"), context.device->dof());
  kp_ = p.real("force_gain");
  kd_ = p.real("force_derivative_gain");
  if ((kp_ > 0.0 || kd_ > 0.0) && !context.device->reports_wrench) {
    throw ParameterError("force_gain", "force feedback needs a device with a force/torque sensor");
  }
  gravity_compensation_ = p.boolean("gravity_compensation");
  error_rate_.configure(1.0 / context.rate_hz, p.real("derivative_filter_hz"));
  friction_compensation_ = p.boolean("friction_compensation");
  const auto& fp = p.real_vector("friction_polynomial");
  const auto& fl = p.real_vector("friction_load");
  for (std::size_t i = 0; i < 5; ++i) friction_p_[i] = fp[i];
  for (std::size_t i = 0; i < 3; ++i) friction_load_[i] = fl[i];
  friction_velocity_max_ = p.real("friction_velocity_max");
  friction_smooth_velocity_ = p.real("friction_smooth_velocity");
  friction_fraction_ = p.real("friction_fraction");
  notch_count_ = 0;
  if (p.real("notch_hz") > 0.0) {
    signal::BiquadCoefficients c;
    try {
      c = signal::BiquadCoefficients::analog_notch(p.real("notch_hz"), p.real("notch_zeta_numerator"),
                                                   p.real("notch_zeta_denominator"), context.rate_hz);
    } catch (const std::invalid_argument& e) {
      throw ParameterError("notch_hz", e.what());
    }
    notch_count_ = static_cast<int>(p.integer("notch_sections"));
    for (int i = 0; i < notch_count_; ++i) notches_[static_cast<std::size_t>(i)].set_coefficients(c);
  }
}

double ImpedanceController::friction(double velocity, double load) const noexcept {
  const double v = std::min(std::abs(velocity), friction_velocity_max_);
  const auto& c = friction_p_;
  const double sliding = (((c[4] * v + c[3]) * v + c[2]) * v + c[1]) * v + c[0];
  const double l = std::abs(load);
  const double load_part = (friction_load_[2] * l + friction_load_[1]) * l + friction_load_[0];
  const double direction = std::clamp(velocity / friction_smooth_velocity_, -1.0, 1.0);
  return friction_fraction_ * direction * std::max(0.0, sliding + load_part);
}

ImpedanceController::Vector6 ImpedanceController::force_error(const ControllerInput& in) const noexcept {
  const ChainState& c = *in.chain;
  Vector6 desired = Vector6::Zero();
  if (in.task.has_wrench) desired << in.task.wrench.force, in.task.wrench.torque;
  Vector6 error = desired;
  if (c.has_operator_wrench) {
    // The device applies -F_h to the operator: e = F_d - (-F_h).
    error.head<3>() += c.operator_wrench.force;
    error.tail<3>() += c.operator_wrench.torque;
  }
  return error;
}

ReturnCode ImpedanceController::activate(const ControllerInput& current, const JointCommand&) noexcept {
  if (current.chain == nullptr || current.chain->model == nullptr) return ReturnCode::error;
  error_rate_.reset(force_error(current));
  // The notches start in the steady state of the present gravity torque: no transient at activation.
  const JointVector start = gravity_compensation_ ? current.chain->data->gravity_torque
                                                  : JointVector(JointVector::Zero(current.chain->velocity.size()));
  for (int i = 0; i < notch_count_; ++i) notches_[static_cast<std::size_t>(i)].reset(start);
  return ReturnCode::ok;
}

ReturnCode ImpedanceController::update(const CycleTime& /*cycle*/, const ControllerInput& in,
                                       JointCommand& command) noexcept {
  const model::ModelData& d = *in.chain->data;
  Vector6 desired = Vector6::Zero();
  if (in.task.has_wrench) desired << in.task.wrench.force, in.task.wrench.torque;
  const Vector6 error = force_error(in);
  const Vector6& rate = error_rate_.update(error);
  const Vector6 wrench = desired + kp_ * error + kd_ * rate;
  command.torque_nm.noalias() = d.frame_jacobian.topRows(rows_).transpose() * wrench.head(rows_);
  if (gravity_compensation_) command.torque_nm += d.gravity_torque;
  if (friction_compensation_) {
    const ChainState& c = *in.chain;
    const JointVector transmitted = model::operator_wrench_torques(c, rows_);
    for (int i = 0; i < command.torque_nm.size(); ++i) {
      command.torque_nm[i] += friction(c.velocity[i], d.gravity_torque[i] - transmitted[i]);
    }
  }
  for (int i = 0; i < notch_count_; ++i) command.torque_nm = notches_[static_cast<std::size_t>(i)].update(command.torque_nm);
  return ReturnCode::ok;
}

}  // namespace hapticd::controllers
