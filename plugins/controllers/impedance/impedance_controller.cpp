#include "impedance_controller.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hapticd/chain_state.hpp"
#include "hapticd/model/task_space.hpp"
#include "hapticd/model/urdf_loader.hpp"

namespace hapticd::controllers {

ParameterSchema ImpedanceController::parameter_schema() {
  ParameterSchema s;
  model::declare_task_parameter(s, "rendered handle wrench");
  s.real("force_gain", "proportional force feedback Kp (0: open-loop impedance control)")
      .minimum(0.0)
      .maximum(50.0)
      .default_value(0.0)
      .tunable();
  s.real("force_derivative_gain", "derivative force feedback Kd")
      .unit("s")
      .minimum(0.0)
      .maximum(1.0)
      .default_value(0.0)
      .tunable();
  s.real("derivative_filter_hz", "low-pass of the force-error derivative")
      .unit("Hz")
      .greater_than(0.0)
      .default_value(100.0);
  s.boolean("gravity_compensation", "add the model's gravity torques").default_value(true);
  declare_friction_parameters(s);  // sliding friction
  // Static friction: variable-structure PID/PD force control.
  s.boolean("stiction_compensation",
            "variable-structure force control: PID at rest, PD with friction "
            "compensation while moving")
      .default_value(false);
  s.real("stiction_integral_gain", "Ki of the force error at rest").unit("1/s").minimum(0.0).default_value(100.0);
  s.real("stiction_integrator_limit_nm", "limit of each joint's integrator")
      .unit("N m")
      .greater_than(0.0)
      .default_value(2.0);
  s.real("stiction_moving_velocity", "relay: a joint counts as moving above this speed")
      .unit("rad/s")
      .greater_than(0.0)
      .default_value(0.05);
  s.real("stiction_rest_velocity", "relay: a moving joint counts as at rest below this speed")
      .unit("rad/s")
      .greater_than(0.0)
      .default_value(0.01);
  // Disturbance observer.
  s.boolean("disturbance_observer", "compensate the disturbance estimated against the rigid-body model")
      .default_value(false);
  s.real("observer_cutoff_hz", "bandwidth of the observer's Q filter").unit("Hz").greater_than(0.0).default_value(15.0);
  s.real("observer_nominal_inertia", "nominal inertia as a share of the model's: below 1 also lightens the device")
      .greater_than(0.0)
      .maximum(1.0)
      .default_value(1.0);
  s.real("observer_limit_nm", "limit of the compensated disturbance per joint")
      .unit("N m")
      .greater_than(0.0)
      .default_value(2.0);
  // Joint-torque feedback.
  s.real("joint_torque_gain", "inner joint-torque loop gain Kt (needs joint torque sensors); 0: off")
      .minimum(0.0)
      .maximum(20.0)
      .default_value(0.0)
      .tunable();
  // Adaptive sliding friction.
  s.boolean("adaptive_friction", "re-tune the sliding-friction model on line (batch least squares)")
      .default_value(false);
  s.real("adaptive_update_s", "re-tuning period T_update").unit("s").greater_than(0.0).default_value(40.0);
  s.integer("adaptive_window", "samples of the backward differences and averages")
      .minimum(2)
      .maximum(kMaxEstimationWindow)
      .default_value(40);
  s.real("adaptive_min_speed", "estimates below this speed are not used")
      .unit("rad/s")
      .greater_than(0.0)
      .default_value(0.05);
  s.real("adaptive_bin_width", "width of the velocity bins").unit("rad/s").greater_than(0.0).default_value(0.05);
  s.real("adaptive_memory", "weight of the earlier data at each update").minimum(0.0).maximum(1.0).default_value(0.5);
  s.real("adaptive_regularization", "ridge weight pulling each fit towards the present curve")
      .minimum(0.0)
      .default_value(0.01);
  s.integer("adaptive_min_bins", "excitation check: filled velocity bins needed")
      .minimum(5)
      .maximum(kFrictionBins)
      .default_value(6);
  s.real("adaptive_min_span", "excitation check: speed range needed").unit("rad/s").minimum(0.0).default_value(0.4);
  s.string("adaptive_log", "CSV of every re-tuning attempt (relative: to the session file); empty: none")
      .default_value(std::string());
  // Resonance.
  s.real("notch_hz", "centre of the torque notch filters (the joint resonance); 0: off")
      .unit("Hz")
      .minimum(0.0)
      .default_value(0.0);
  s.integer("notch_sections", "notch sections in series").minimum(1).maximum(4).default_value(2);
  s.real("notch_zeta_numerator", "damping ratio of the notch zeros (depth = numerator / denominator)")
      .minimum(0.0)
      .default_value(0.01);
  s.real("notch_zeta_denominator", "damping ratio of the notch poles (width)").greater_than(0.0).default_value(0.2);
  return s;
}

void ImpedanceController::configure(const Parameters& p, const PluginContext& context) {
  if (context.device == nullptr || context.device->robot_model_file.empty()) {
    throw ParameterError("task", "impedance control needs a device with a robot model");
  }
  dof_ = context.device->dof();
  rows_ = model::task_rows(p.string("task"), dof_);
  reports_wrench_ = context.device->reports_wrench;
  reports_joint_torque_ = context.device->reports_joint_torque;
  apply(gains_of(p));
  gravity_compensation_ = p.boolean("gravity_compensation");
  error_rate_.configure(1.0 / context.rate_hz, p.real("derivative_filter_hz"));
  configure_friction(p, context);

  disturbance_observer_ = p.boolean("disturbance_observer");
  if (disturbance_observer_) {
    try {
      observer_.configure(dof_, context.rate_hz, p.real("observer_cutoff_hz"), p.real("observer_limit_nm"),
                          p.real("observer_nominal_inertia"));
    } catch (const std::invalid_argument& e) {
      throw ParameterError("observer_cutoff_hz", e.what());
    }
  }

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
  sliding_.setZero(dof_);
  friction_torque_.setZero(dof_);
  projected_error_.setZero(dof_);
  previous_command_.setZero(dof_);
}

ImpedanceController::Gains ImpedanceController::gains_of(const Parameters& p) const {
  const Gains g{p.real("force_gain"), p.real("force_derivative_gain"), p.real("joint_torque_gain")};
  if ((g.kp > 0.0 || g.kd > 0.0) && !reports_wrench_)
    throw ParameterError("force_gain", "force feedback needs a device with a force/torque sensor");
  if (g.kt > 0.0 && !reports_joint_torque_)
    throw ParameterError("joint_torque_gain", "joint-torque feedback needs a device that reports joint torques");
  return g;
}

void ImpedanceController::apply(const Gains& gains) noexcept {
  kp_ = gains.kp;
  kd_ = gains.kd;
  joint_torque_gain_ = gains.kt;
}

void ImpedanceController::tune(const Parameters& parameters) { gains_inbox_.publish(gains_of(parameters)); }

void ImpedanceController::configure_friction(const Parameters& p, const PluginContext& context) {
  friction_compensation_ = p.boolean("friction_compensation");
  stiction_compensation_ = p.boolean("stiction_compensation");
  adaptive_ = p.boolean("adaptive_friction");
  if (adaptive_ && !friction_compensation_) {
    throw ParameterError("adaptive_friction", "re-tunes the sliding-friction compensation: set friction_compensation");
  }
  configure_friction_compensation(p, context, dof_, friction_);

  StictionSettings st;
  st.integral_gain = p.real("stiction_integral_gain");
  st.integrator_limit_nm = p.real("stiction_integrator_limit_nm");
  st.moving_velocity = p.real("stiction_moving_velocity");
  st.rest_velocity = p.real("stiction_rest_velocity");
  if (st.rest_velocity >= st.moving_velocity) {
    throw ParameterError("stiction_rest_velocity", "must be below stiction_moving_velocity (relay hysteresis)");
  }
  if (stiction_compensation_ && !context.device->reports_wrench) {
    throw ParameterError("stiction_compensation", "the variable-structure controller needs a force/torque sensor");
  }
  stiction_.configure(dof_, st, 1.0 / context.rate_hz);

  retuner_.reset();
  if (adaptive_) {
    const double update_s = p.real("adaptive_update_s");
    adapt_period_cycles_ =
        std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(update_s * context.rate_hz)));
    estimator_.configure(dof_, 1.0 / context.rate_hz, static_cast<int>(p.integer("adaptive_window")),
                         p.real("adaptive_bin_width"), p.real("adaptive_min_speed"));
    RetuneChecks checks;
    checks.memory = p.real("adaptive_memory");
    checks.min_bins = static_cast<int>(p.integer("adaptive_min_bins"));
    checks.min_span = p.real("adaptive_min_span");
    checks.fraction = p.real("friction_fraction");
    checks.regularization = p.real("adaptive_regularization");
    std::filesystem::path log = p.string("adaptive_log");
    if (!log.empty() && log.is_relative()) log = context.config_directory / log;
    retuner_ = std::make_unique<FrictionRetuner>();
    try {
      retuner_->start(dof_, friction_.models(), checks, log);
    } catch (const std::runtime_error& e) {
      throw ParameterError("adaptive_log", e.what());
    }
  }
}

ImpedanceController::Vector6 ImpedanceController::force_error(const ControllerInput& in) const noexcept {
  const ChainState& c = in.chain;
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

Outcome ImpedanceController::activate(const ControllerInput& current, const JointCommand& last_command) {
  if (current.chain.model == nullptr)
    return Outcome::failure("the impedance controller needs the device's robot model");
  error_rate_.reset(force_error(current));
  // The notches start in the steady state of the present gravity torque: no transient at activation.
  const JointVector start = gravity_compensation_
                                ? current.chain.data->gravity_torque
                                : JointVector(JointVector::Zero(current.device.joints.velocity.size()));
  for (int i = 0; i < notch_count_; ++i) notches_[static_cast<std::size_t>(i)].reset(start);
  stiction_.reset();
  if (disturbance_observer_) observer_.reset(current.device.joints.velocity);
  previous_command_ = last_command.torque_nm.size() == dof_ ? last_command.torque_nm : start;
  if (adaptive_) {
    estimator_.reset(current.device.joints.position);
    adapt_cycles_ = 0;
    retuned_pending_ = false;
  }
  return Outcome::success();
}

void ImpedanceController::adapt(const CycleTime& cycle, const ControllerInput& in,
                                const JointVector& operator_torques) noexcept {
  estimator_.sample(in.device.joints.position, previous_command_, operator_torques, *in.chain.data, friction_);
  if (retuner_->take(retuned_)) retuned_pending_ = true;
  if (++adapt_cycles_ < adapt_period_cycles_) return;
  adapt_cycles_ = 0;
  // Results fitted to the previous hand-over take effect at this period boundary (deterministic timing as long as
  // the worker needs less than T_update, which it does by orders of magnitude).
  if (retuned_pending_) {
    friction_.set_models(retuned_.models);
    retuned_pending_ = false;
  }
  FrictionBinData& bins = estimator_.bins();
  bins.sequence = ++adapt_sequence_;
  bins.time_s = static_cast<double>(cycle.time_ns) * 1e-9;
  retuner_->submit(bins);
  bins.clear();
}

Outcome ImpedanceController::update(const CycleTime& cycle, const ControllerInput& in, JointCommand& command) {
  if (gains_inbox_.take(gains_incoming_)) apply(gains_incoming_);  // run-time gains, at a cycle boundary
  const ChainState& c = in.chain;
  const model::ModelData& d = *c.data;
  Vector6 desired = Vector6::Zero();
  if (in.task.has_wrench) desired << in.task.wrench.force, in.task.wrench.torque;
  const Vector6 error = force_error(in);
  const Vector6& rate = error_rate_.update(error);
  const Vector6 wrench = desired + kp_ * error + kd_ * rate;
  command.torque_nm.noalias() = d.frame_jacobian.topRows(rows_).transpose() * wrench.head(rows_);
  if (gravity_compensation_) command.torque_nm += d.gravity_torque;

  const JointVector operator_torques = model::operator_wrench_torques(c, rows_);
  if (adaptive_) adapt(cycle, in, operator_torques);
  if (friction_compensation_ || stiction_compensation_) {
    for (int i = 0; i < dof_; ++i) {
      sliding_[i] = friction_compensation_
                        ? friction_.torque(i, in.device.joints.velocity[i], d.gravity_torque[i] - operator_torques[i])
                        : 0.0;
    }
    if (stiction_compensation_) {
      projected_error_.noalias() = d.frame_jacobian.topRows(rows_).transpose() * error.head(rows_);
      stiction_.update(in.device.joints.velocity, sliding_, projected_error_, friction_torque_);
      command.torque_nm += friction_torque_;
    } else {
      command.torque_nm += sliding_;
    }
  }
  if (disturbance_observer_)
    command.torque_nm += observer_.update(d, in.device.joints.velocity, previous_command_, operator_torques);
  if (joint_torque_gain_ > 0.0) {
    command.torque_nm += joint_torque_gain_ * (command.torque_nm - in.device.joints.effort);
  }
  for (int i = 0; i < notch_count_; ++i)
    command.torque_nm = notches_[static_cast<std::size_t>(i)].update(command.torque_nm);
  previous_command_ = command.torque_nm;
  return Outcome::success();
}

}  // namespace hapticd::controllers
