#include "redundancy_ik.hpp"

#include "hapticd/chain_state.hpp"
#include "hapticd/model/dynamics.hpp"
#include "hapticd/model/kinematics.hpp"
#include "hapticd/model/task_space.hpp"
#include "hapticd/model/urdf_loader.hpp"

namespace hapticd::ik {
namespace {

model::InverseKind inverse_kind(const std::string& name) {
  if (name == "weighted") return model::InverseKind::weighted;
  if (name == "damped") return model::InverseKind::damped;
  if (name == "inertia_weighted") return model::InverseKind::inertia_weighted;
  return model::InverseKind::pseudoinverse;
}

}  // namespace

ParameterSchema RedundancyIk::parameter_schema() {
  ParameterSchema s;
  model::declare_task_parameter(s, "task rows");
  s.string("inverse",
           "generalised inverse: pseudoinverse (SVD), weighted (joint_weights), damped "
           "(singularity-robust, damping), inertia_weighted (dynamically consistent)")
      .choices({"pseudoinverse", "weighted", "damped", "inertia_weighted"})
      .default_value(std::string("pseudoinverse"));
  s.real_vector("joint_weights",
                "weighted, damped: W = diag(joint_weights), one positive value per joint; the "
                "solution minimises qd^T W qd (empty: all 1)")
      .default_value(std::vector<double>{});
  s.real("damping", "damped: lambda of J^T (J J^T + lambda^2 I)^-1 (task units)")
      .minimum(0.0)
      .maximum(10.0)
      .default_value(0.02);
  s.string("level",
           "how the joint target is integrated: velocity (qd from J^W#, q integrated) or acceleration "
           "(qdd from J^W#, stabilised self-motion)")
      .choices({"velocity", "acceleration"})
      .default_value(std::string("velocity"));
  s.real("tracking_bandwidth_rad_s",
         "feedback of the pose error of the integrated target (velocity level: "
         "kp = w; acceleration level: kp = w^2, kd = 2 w)")
      .unit("rad/s")
      .greater_than(0.0)
      .maximum(2000.0)
      .default_value(100.0);
  s.real("null_space_gain", "k of the null-space descent qd0 = -k W^-1 grad H")
      .minimum(0.0)
      .maximum(1000.0)
      .default_value(1.0)
      .tunable();
  s.real("null_space_damping",
         "d: the self-motion velocity relaxes towards qd0 at this rate (acceleration and "
         "torque level)")
      .unit("1/s")
      .minimum(0.0)
      .maximum(1000.0)
      .default_value(20.0)
      .tunable();
  s.real("manipulability", "weight of -sqrt(det(J J^T))").minimum(0.0).default_value(0.0);
  s.real("condition_number", "weight of the condition number of J").minimum(0.0).default_value(0.0);
  s.real("smallest_singular_value", "weight of -sigma_min(J)").minimum(0.0).default_value(0.0);
  s.real("characteristic_length_m", "scales the angular rows against the linear ones in the Jacobian criteria")
      .unit("m")
      .greater_than(0.0)
      .default_value(0.3);
  s.real("wrist", "weight of the wrist criterion ((q_k - target) / (pi/2))^2").minimum(0.0).default_value(0.0);
  s.integer("wrist_joint", "the joint k of the wrist criterion, 1-based (ViSHaRD10: 9)")
      .minimum(1)
      .maximum(kMaxJoints)
      .default_value(std::int64_t{9});
  s.real("wrist_target_rad", "the wrist criterion's target").unit("rad").default_value(1.5707963267948966);
  s.real("joint_limits", "weight of the joint-limit distance sum ((q - mid) / range)^2 (limited joints only)")
      .minimum(0.0)
      .default_value(0.0);
  s.real("keep_out", "weight of the keep-out sphere criterion").minimum(0.0).default_value(0.0);
  s.string("keep_out_frame", "the frame kept out of the sphere (empty: the handle)").default_value(std::string());
  s.real_vector("keep_out_center_m", "centre of the keep-out sphere, world")
      .size(3)
      .default_value(std::vector<double>{0.0, 0.0, 0.0});
  s.real("keep_out_radius_m", "radius of the keep-out sphere").unit("m").minimum(0.0).default_value(0.1);
  s.real("keep_out_margin_m", "the criterion rises from zero this far from the sphere")
      .unit("m")
      .greater_than(0.0)
      .default_value(0.1);
  s.real("clearance",
         "weight of the clearance criterion ((margin - d) / margin)^2, d the distance to the nearest other device "
         "of the group (docs/multi-device.md): the arm moves away from it in the null space")
      .minimum(0.0)
      .default_value(0.0);
  s.real("clearance_margin_m", "the clearance criterion rises from zero this close to another device")
      .unit("m")
      .greater_than(0.0)
      .maximum(2.0)
      .default_value(0.15);
  s.real("acceleration_filter_hz", "velocity level: low-pass of the differentiated joint-velocity target")
      .unit("Hz")
      .greater_than(0.0)
      .default_value(200.0);
  return s;
}

void RedundancyIk::configure(const Parameters& p, const PluginContext& context) {
  if (context.device == nullptr || context.robot_model == nullptr)
    throw ParameterError("task", "redundancy_ik needs a device with a robot model");
  model_ = context.robot_model;
  data_ = std::make_unique<model::ModelData>(*model_);
  const int n = model_->dof();
  handle_ = model_->require_frame(context.device->handle_frame.empty() ? "handle" : context.device->handle_frame);
  rows_ = model::task_rows(p.string("task"), n);
  level_ = p.string("level") == "acceleration" ? Level::acceleration : Level::velocity;
  const double w = p.real("tracking_bandwidth_rad_s");
  kp_ = level_ == Level::velocity ? w : w * w;
  kd_ = 2.0 * w;
  null_gain_ = p.real("null_space_gain");
  null_damping_ = p.real("null_space_damping");

  const auto& weights = p.real_vector("joint_weights");
  JointVector wv = JointVector::Ones(n);
  if (!weights.empty()) {
    if (static_cast<int>(weights.size()) != n)
      throw ParameterError("joint_weights",
                           "needs " + std::to_string(n) + " values, got " + std::to_string(weights.size()));
    for (int i = 0; i < n; ++i) {
      if (!(weights[static_cast<std::size_t>(i)] > 0.0))
        throw ParameterError("joint_weights", "weights must be positive");
      wv[i] = weights[static_cast<std::size_t>(i)];
    }
  }
  const model::InverseKind kind = inverse_kind(p.string("inverse"));
  const double damping = p.real("damping");
  inverse_.configure(kind, n, wv, damping);
  measured_.configure(kind, n, wv, damping);
  dynamic_.configure(model::InverseKind::inertia_weighted, n, wv);

  model::SideCriteriaSettings c;
  c.frame = handle_;
  c.task_rows = rows_;
  c.characteristic_length_m = p.real("characteristic_length_m");
  c.manipulability = p.real("manipulability");
  c.condition_number = p.real("condition_number");
  c.smallest_singular_value = p.real("smallest_singular_value");
  c.wrist = p.real("wrist");
  c.wrist_joint = static_cast<int>(p.integer("wrist_joint")) - 1;
  if (c.wrist != 0.0 && c.wrist_joint >= n)
    throw ParameterError("wrist_joint",
                         "joint " + std::to_string(c.wrist_joint + 1) + " outside 1.." + std::to_string(n));
  c.wrist_target_rad = p.real("wrist_target_rad");
  c.joint_limits = p.real("joint_limits");
  c.keep_out = p.real("keep_out");
  const std::string& keep_out_frame = p.string("keep_out_frame");
  if (!keep_out_frame.empty()) {
    c.keep_out_frame = model_->frame_id(keep_out_frame);
    if (c.keep_out_frame < 0) throw ParameterError("keep_out_frame", "the model has no frame '" + keep_out_frame + "'");
  }
  const auto& centre = p.real_vector("keep_out_center_m");
  c.keep_out_center = Eigen::Vector3d(centre[0], centre[1], centre[2]);
  c.keep_out_radius_m = p.real("keep_out_radius_m");
  c.keep_out_margin_m = p.real("keep_out_margin_m");
  criteria_.configure(*model_, c);
  clearance_weight_ = p.real("clearance");
  clearance_margin_ = p.real("clearance_margin_m");

  acceleration_.configure(1.0 / context.rate_hz, p.real("acceleration_filter_hz"));
  q_.setZero(n);
  qd_.setZero(n);
  gradient_.setZero(n);
  jacobian_.setZero(6, n);
}

void RedundancyIk::tune(const Parameters& p) {
  gains_inbox_.publish({p.real("null_space_gain"), p.real("null_space_damping")});
}

Outcome RedundancyIk::activate(const InverseKinematicsInput& current) {
  q_ = current.device.joints.position;
  qd_ = current.device.joints.velocity;
  acceleration_.reset(qd_);
  gradient_.setZero(q_.size());
  return q_.size() == model_->dof() ? Outcome::success()
                                    : Outcome::failure("the device's joints do not match the robot model");
}

Outcome RedundancyIk::update(const CycleTime& cycle, const InverseKinematicsInput& in, JointTarget& target) {
  if (NullSpaceGains g; gains_inbox_.take(g)) {  // run-time gains, at a cycle boundary
    null_gain_ = g.gain;
    null_damping_ = g.damping;
  }
  if (!in.task.has_motion)
    return Outcome::failure("no desired motion: the scheme needs an admittance-type virtual model");
  const double dt = static_cast<double>(cycle.period_ns) * 1e-9;
  Eigen::Isometry3d desired = Eigen::Isometry3d::Identity();
  desired.translation() = in.task.pose.position;
  desired.linear() = in.task.pose.orientation.toRotationMatrix();
  const bool own_inertia = inverse_.kind() == model::InverseKind::inertia_weighted &&
                           (in.chain.data == nullptr || in.chain.data->mass_llt.rows() != model_->dof());
  model::forward_velocity(*model_, *data_, q_, qd_,
                          own_inertia ? model::BodyInertias::update : model::BodyInertias::skip);
  model::frame_jacobian(*model_, *data_, handle_, jacobian_);
  const model::TaskJacobian j = jacobian_.topRows(rows_);
  // The inertia-weighted inverse at the target takes the inertia the server factored at the measured joints
  // this cycle (the target tracks them; any positive definite weighting keeps J J^W# = I): the same weighting as
  // the controller's resolution, and no second factorisation of M per cycle.
  const Eigen::LLT<JointMatrix>* mass = &data_->mass_llt;
  if (own_inertia) {
    model::joint_space_inertia(*model_, *data_);
  } else if (inverse_.kind() == model::InverseKind::inertia_weighted) {
    mass = &in.chain.data->mass_llt;
  }
  inverse_.compute(j, mass);
  const model::Vector6d error = model::pose_difference(desired, model::frame_pose(*model_, *data_, handle_));
  model::Vector6d xd;
  xd << in.task.twist.linear, in.task.twist.angular;
  // The side criterion once per cycle, at the measured joints: the resolution the controller asks for at the
  // measured state needs it there, and the integrated target tracks the measured joints closely enough to share
  // it (a target that drifted from them in the null space serves no controller of this chain).
  criterion_ = 0.0;
  if (criteria_.empty()) {
    gradient_.setZero(model_->dof());
  } else {
    criterion_ = criteria_.evaluate(in.device.joints.position, gradient_, in.chain.data);
  }
  criterion_ += add_clearance_term(in.chain.neighbour);
  const JointVector qd0 = -null_gain_ * inverse_.weight_inverse_times(gradient_);
  if (level_ == Level::velocity) {
    qd_ = model::resolve_velocity(inverse_, model::TaskVector((xd + kp_ * error).head(rows_)), qd0);
    q_ += qd_ * dt;
    target.acceleration = acceleration_.update(qd_);
  } else {
    model::Vector6d xdd;
    xdd << in.task.acceleration.linear, in.task.acceleration.angular;
    model::Vector6d current;
    current.noalias() = jacobian_ * qd_;
    xdd += kd_ * (xd - current) + kp_ * error - model::frame_jacobian_dot_times_qd(*model_, *data_, handle_);
    const JointVector qdd0 = null_damping_ * (qd0 - qd_);
    const JointVector qdd = model::resolve_acceleration(inverse_, model::TaskVector(xdd.head(rows_)), qdd0);
    qd_ += qdd * dt;
    q_ += qd_ * dt;
    target.acceleration = qdd;
  }
  target.position = q_;
  target.velocity = qd_;
  target.valid = true;
  return q_.allFinite() ? Outcome::success() : Outcome::failure("the joint solution is not finite");
}

double RedundancyIk::add_clearance_term(const NeighbourClearance& neighbour) noexcept {
  // H = w ((m - d) / m)^2 below the margin, grad H = -2 w (m - d) / m^2 grad d (the group stage's gradient).
  if (clearance_weight_ == 0.0 || !neighbour.present() || neighbour.gradient.size() != gradient_.size()) return 0.0;
  const double depth = clearance_margin_ - neighbour.distance_m;
  if (!(depth > 0.0)) return 0.0;
  const double m2 = clearance_margin_ * clearance_margin_;
  gradient_.noalias() -= (2.0 * clearance_weight_ * depth / m2) * neighbour.gradient;
  return clearance_weight_ * depth * depth / m2;
}

JointVector RedundancyIk::task_acceleration(const DeviceState& device, const ChainState& chain,
                                            const model::TaskVector& xdd_minus_bias) noexcept {
  const model::ModelData& d = *chain.data;
  measured_.compute(d.frame_jacobian.topRows(xdd_minus_bias.size()), &d.mass_llt);
  const JointVector qd0 = -null_gain_ * measured_.weight_inverse_times(gradient_);
  return model::resolve_acceleration(measured_, xdd_minus_bias,
                                     JointVector(null_damping_ * (qd0 - device.joints.velocity)));
}

JointVector RedundancyIk::null_space_torque(const DeviceState& device, const ChainState& chain, int rows) noexcept {
  const model::ModelData& d = *chain.data;
  const model::TaskJacobian j = d.frame_jacobian.topRows(rows);
  dynamic_.compute(j, &d.mass_llt);
  // tau0 = M d (qd0 - qd) with qd0 = -k M^-1 grad H: d (-k grad H - M qd).
  JointVector tau0 = -null_gain_ * gradient_;
  tau0.noalias() -= d.mass_matrix * device.joints.velocity;
  tau0 *= null_damping_;
  return model::null_space_torque(dynamic_, j, tau0);
}

}  // namespace hapticd::ik
