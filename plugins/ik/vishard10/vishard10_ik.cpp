#include "vishard10_ik.hpp"

#include <cmath>
#include <filesystem>
#include <numbers>

#include "hapticd/chain_state.hpp"
#include "hapticd/model/kinematics.hpp"
#include "hapticd/model/urdf_loader.hpp"

namespace hapticd::ik {
namespace {

constexpr double kPi = std::numbers::pi;

// The SCARA tip (joint 5's axis) for joints 1-4, and its 2 x 4 Jacobian.
Eigen::Vector2d scara_tip(const vishard10::Geometry& g, const double q[4], Eigen::Matrix<double, 2, 4>* jacobian) {
  Eigen::Vector2d p = g.base;
  double yaw = 0.0;
  Eigen::Vector2d link[4];
  for (int i = 0; i < 4; ++i) {
    yaw += q[i];
    link[i] = g.scara_link[static_cast<std::size_t>(i)] * Eigen::Vector2d(std::cos(yaw), std::sin(yaw));
    p += link[i];
  }
  if (jacobian != nullptr) {
    Eigen::Vector2d beyond = Eigen::Vector2d::Zero();
    for (int i = 3; i >= 0; --i) {
      beyond += link[i];
      jacobian->col(i) = Eigen::Vector2d(-beyond.y(), beyond.x());
    }
  }
  return p;
}

double scara_manipulability(const vishard10::Geometry& g, const double q[4]) {
  Eigen::Matrix<double, 2, 4> j;
  (void)scara_tip(g, q, &j);
  return std::sqrt(std::max(0.0, (j * j.transpose()).determinant()));
}

}  // namespace

ParameterSchema Vishard10Ik::parameter_schema() {
  ParameterSchema s;
  s.string("scara",
           "joints 1-4: inverse_function (two prismatic pairs), lookup_table (the optimised table of "
           "hapticd-scara-lut, scara_table) or pseudoinverse (with the manipulability criterion; failed on "
           "hardware, kept as an option)")
      .choices({"inverse_function", "lookup_table", "pseudoinverse"})
      .default_value(std::string("inverse_function"));
  s.string("scara_table", "lookup_table: the table file (relative paths: from the session file's folder)")
      .default_value(std::string());
  s.real("scara_axes_yaw_rad", "inverse function: pair 1-2 moves along this world direction, pair 3-4 across it")
      .unit("rad")
      .default_value(0.0);
  s.integer("scara_branch_12", "inverse function: elbow side of pair 1-2 (+1 or -1)")
      .minimum(-1)
      .maximum(1)
      .default_value(std::int64_t{1});
  s.integer("scara_branch_34", "inverse function: elbow side of pair 3-4 (+1 or -1)")
      .minimum(-1)
      .maximum(1)
      .default_value(std::int64_t{1});
  s.real("scara_extension_limit",
         "inverse function: the usable rectangle, as a share of each pair's reach "
         "(targets beyond are clamped: the handle stops there)")
      .greater_than(0.0)
      .maximum(0.999)
      .default_value(0.95);
  s.real("scara_manipulability", "pseudoinverse: gain of the manipulability criterion").minimum(0.0).default_value(1.0);
  s.string("wrist",
           "the orientation: inverse_function (link 5 keeps the world yaw q5_0) or pseudoinverse (weighted, "
           "with the wrist criterion and the virtual wall on joint 9)")
      .choices({"inverse_function", "pseudoinverse"})
      .default_value(std::string("inverse_function"));
  s.real("q5_0_rad",
         "inverse function: the world yaw of link 5 (places the wrist singularity: the handle axis "
         "horizontal along this yaw)")
      .unit("rad")
      .default_value(0.0);
  s.real_vector("wrist_weights", "pseudoinverse: W on q5', q8', q9, q10 (slow the heavy joint 5, favour joint 10)")
      .size(4)
      .minimum(1e-6)
      .default_value(std::vector<double>{3.0, 0.2, 1.0, 0.1});
  s.real("wrist_criterion", "pseudoinverse: gain k of the null-space descent of (q9 - pi/2)^2")
      .minimum(0.0)
      .default_value(1.0);
  s.real("wall_zeta_rad", "pseudoinverse: the virtual wall keeps q9 in [zeta, pi - zeta] (0: no wall)")
      .unit("rad")
      .minimum(0.0)
      .maximum(0.785)
      .default_value(0.35);
  s.real("wall_gain", "pseudoinverse: stiffness of the virtual wall in the null space")
      .minimum(0.0)
      .default_value(50.0);
  s.real("tracking_bandwidth_rad_s", "pseudoinverse parts: feedback of the integrated target's pose error")
      .unit("rad/s")
      .greater_than(0.0)
      .maximum(2000.0)
      .default_value(100.0);
  s.real("activation_tolerance_rad",
         "inverse functions: the device must stand within this of the function's "
         "posture for its pose at activation")
      .unit("rad")
      .greater_than(0.0)
      .default_value(0.05);
  s.real("acceleration_filter_hz", "low-pass of the differentiated joint-velocity target")
      .unit("Hz")
      .greater_than(0.0)
      .default_value(200.0);
  return s;
}

void Vishard10Ik::configure(const Parameters& p, const PluginContext& context) {
  if (context.device == nullptr || context.robot_model == nullptr)
    throw ParameterError("scara", "vishard10_ik needs a device with a robot model");
  world_to_base_ = to_isometry(context.base_pose).inverse();
  model_ = std::make_unique<const model::RobotModel>(context.robot_model->with_base(world_to_base_));
  handle_ = model_->require_frame(context.device->handle_frame.empty() ? "handle" : context.device->handle_frame);
  try {
    geometry_ = vishard10::Geometry::from(*model_, handle_);
  } catch (const std::invalid_argument& e) {
    throw ParameterError("scara", e.what());
  }
  data_ = std::make_unique<model::ModelData>(*model_);
  const std::string& scara = p.string("scara");
  scara_ = scara == "lookup_table"    ? Scara::lookup_table
           : scara == "pseudoinverse" ? Scara::pseudoinverse
                                      : Scara::inverse_function;
  if (scara_ == Scara::lookup_table) {
    const std::string& file = p.string("scara_table");
    if (file.empty()) throw ParameterError("scara_table", "scara: lookup_table needs a table file (hapticd-scara-lut)");
    std::filesystem::path path(file);
    if (path.is_relative()) path = context.config_directory / path;
    try {
      table_ = vishard10::ScaraTable::load(path);
    } catch (const std::runtime_error& e) {
      throw ParameterError("scara_table", e.what());
    }
  }
  wrist_function_ = p.string("wrist") == "inverse_function";
  scara_yaw_ = p.real("scara_axes_yaw_rad");
  branch12_ = p.integer("scara_branch_12") >= 0 ? 1 : -1;
  branch34_ = p.integer("scara_branch_34") >= 0 ? 1 : -1;
  scara_limit_ = p.real("scara_extension_limit");
  scara_manipulability_ = p.real("scara_manipulability");
  q5_0_ = p.real("q5_0_rad");
  const auto& w = p.real_vector("wrist_weights");
  wrist_weights_.resize(4);
  for (int i = 0; i < 4; ++i) wrist_weights_[i] = w[static_cast<std::size_t>(i)];
  wrist_inverse_.configure(model::InverseKind::weighted, 4, wrist_weights_);
  wrist_criterion_ = p.real("wrist_criterion");
  wall_zeta_ = p.real("wall_zeta_rad");
  wall_gain_ = p.real("wall_gain");
  kp_ = p.real("tracking_bandwidth_rad_s");
  activation_tolerance_ = p.real("activation_tolerance_rad");
  acceleration_.configure(1.0 / context.rate_hz, p.real("acceleration_filter_hz"));
  q_.setZero(10);
  previous_.setZero(10);
  qd_.setZero(10);
  jacobian_.setZero(6, 10);
}

void Vishard10Ik::solve_scara(const Eigen::Vector2d& target, const Eigen::Vector2d& velocity, double dt) noexcept {
  if (scara_ == Scara::inverse_function) {
    if (!vishard10::scara_inverse_function(geometry_, target, scara_yaw_, branch12_, branch34_, scara_q_, scara_limit_))
      ++clamped_;
    return;
  }
  if (scara_ == Scara::lookup_table) {
    if (!table_.solve(geometry_, target - geometry_.base, scara_q_)) ++clamped_;
    return;
  }
  // Pseudoinverse of the 2 x 4 SCARA Jacobian, the manipulability gradient in its null space.
  Eigen::Matrix<double, 2, 4> j;
  const Eigen::Vector2d tip = scara_tip(geometry_, scara_q_, &j);
  const Eigen::Vector2d xd = velocity + kp_ * (target - tip);
  const Eigen::Matrix2d jjt = j * j.transpose() + 1e-9 * Eigen::Matrix2d::Identity();
  const Eigen::Matrix<double, 4, 2> pinv = j.transpose() * jjt.inverse();
  Eigen::Vector4d gradient;
  const double base = scara_manipulability(geometry_, scara_q_);
  for (int i = 0; i < 4; ++i) {
    double probe[4] = {scara_q_[0], scara_q_[1], scara_q_[2], scara_q_[3]};
    probe[i] += 1e-6;
    gradient[i] = (scara_manipulability(geometry_, probe) - base) / 1e-6;
  }
  const Eigen::Vector4d qd = pinv * xd + (Eigen::Matrix4d::Identity() - pinv * j) * (scara_manipulability_ * gradient);
  for (int i = 0; i < 4; ++i) scara_q_[i] += qd[i] * dt;
}

void Vishard10Ik::solve_wrist(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& angular_velocity,
                              double dt) noexcept {
  if (wrist_function_) {
    rot_q_[0] = q5_0_;
    (void)vishard10::wrist_inverse_function(rotation, q5_0_, rot_q_[1], rot_q_[2], rot_q_[3]);
    return;
  }
  // Weighted pseudoinverse of the 3 x 4 angular Jacobian of q_rot: its columns are the joint axes of 5, 8, 9, 10.
  Eigen::Matrix<double, 3, 4> axes;
  const Eigen::Matrix3d now = vishard10::wrist_axes(rot_q_[0], rot_q_[1], rot_q_[2], rot_q_[3], axes);
  wrist_inverse_.compute(model::TaskJacobian(axes));
  const Eigen::AngleAxisd error(rotation * now.transpose());
  model::TaskVector w(3);
  w = angular_velocity + kp_ * error.angle() * error.axis();
  // Null space: descend (q9 - pi/2)^2 and the wall beyond [zeta, pi - zeta].
  JointVector gradient = JointVector::Zero(4);
  const double q9 = rot_q_[2];
  gradient[2] = wrist_criterion_ * 2.0 * (q9 - kPi / 2);
  if (wall_zeta_ > 0.0) {
    if (q9 < wall_zeta_) gradient[2] += wall_gain_ * 2.0 * (q9 - wall_zeta_);
    if (q9 > kPi - wall_zeta_) gradient[2] += wall_gain_ * 2.0 * (q9 - (kPi - wall_zeta_));
  }
  const JointVector qd =
      model::resolve_velocity(wrist_inverse_, w, JointVector(-wrist_inverse_.weight_inverse_times(gradient)));
  for (int i = 0; i < 4; ++i) rot_q_[i] += qd[i] * dt;
}

const JointVector& Vishard10Ik::solve(const Pose& pose, const Twist& twist, double dt) noexcept {
  const Eigen::Matrix3d rotation = pose.orientation.toRotationMatrix();
  double q6 = 0.0, q7 = 0.0;
  if (!vishard10::prismatic_pair(geometry_, pose.position.z(), q6, q7)) ++clamped_;
  solve_wrist(rotation, twist.angular, dt);
  Eigen::Vector2d target = pose.position.head<2>();
  solve_scara(target, twist.linear.head<2>(), dt);
  const auto assemble = [&] {
    q_[0] = scara_q_[0];
    q_[1] = scara_q_[1];
    q_[2] = scara_q_[2];
    q_[3] = scara_q_[3];
    q_[4] = rot_q_[0] - vishard10::scara_link4_yaw(scara_q_);
    q_[5] = q6;
    q_[6] = q7;
    q_[7] = rot_q_[1] - (q6 + q7);
    q_[8] = rot_q_[2];
    q_[9] = rot_q_[3];
  };
  assemble();
  if (scara_ != Scara::pseudoinverse) {
    // l6 and l7 differ by 0.1 mm: the pair leaves the handle that far off joint 5's axis, sideways. One shift of
    // the SCARA target removes it (the offset depends on q6 and q5' only, not on joints 1-4).
    model::forward_kinematics(*model_, *data_, q_, model::BodyInertias::skip);
    const Eigen::Vector2d off =
        pose.position.head<2>() - model::frame_pose(*model_, *data_, handle_).translation().head<2>();
    solve_scara(target + off, Eigen::Vector2d::Zero(), dt);
    assemble();
  }
  if (!first_)
    for (int i = 0; i < 10; ++i) q_[i] = vishard10::unwrap_near(q_[i], previous_[i]);
  return q_;
}

void Vishard10Ik::reset(const JointVector& q) noexcept {
  for (int i = 0; i < 4; ++i) scara_q_[i] = q[i];
  rot_q_[0] = q[0] + q[1] + q[2] + q[3] + q[4];
  rot_q_[1] = q[5] + q[6] + q[7];
  rot_q_[2] = q[8];
  rot_q_[3] = q[9];
  previous_ = q;
  first_ = false;
  clamped_ = 0;
}

Outcome Vishard10Ik::activate(const InverseKinematicsInput& current) {
  const JointVector& measured = current.device.joints.position;
  if (measured.size() != 10) return Outcome::failure("the ViSHaRD10 inverse kinematics needs a 10-joint device");
  reset(measured);
  model::forward_kinematics(*model_, *data_, measured);
  const Eigen::Isometry3d at = model::frame_pose(*model_, *data_, handle_);
  Pose pose;
  pose.position = at.translation();
  pose.orientation = Eigen::Quaterniond(at.linear());
  const JointVector& q = solve(pose, Twist{}, 0.0);
  // An inverse function has one posture per pose: the device must stand in it (else the first target jumps).
  if ((q - measured).cwiseAbs().maxCoeff() > activation_tolerance_)
    return Outcome::failure("the measured joints are not a configuration of the analytic solution");
  previous_ = q;
  qd_.setZero(10);
  acceleration_.reset(qd_);
  return Outcome::success();
}

Outcome Vishard10Ik::update(const CycleTime& cycle, const InverseKinematicsInput& in, JointTarget& target) {
  if (!in.task.has_motion)
    return Outcome::failure("no desired motion: the scheme needs an admittance-type virtual model");
  const double dt = static_cast<double>(cycle.period_ns) * 1e-9;
  const Eigen::Matrix3d to_base = world_to_base_.linear();
  Pose pose;
  pose.position = world_to_base_ * in.task.pose.position;
  pose.orientation = Eigen::Quaterniond(to_base) * in.task.pose.orientation;
  const Twist twist{to_base * in.task.twist.linear, to_base * in.task.twist.angular};
  const JointVector& q = solve(pose, twist, dt);
  qd_ = (q - previous_) / dt;
  previous_ = q;
  target.position = q;
  target.velocity = qd_;
  target.acceleration = acceleration_.update(qd_);
  target.valid = true;
  return q.allFinite() ? Outcome::success() : Outcome::failure("the joint solution is not finite");
}

}  // namespace hapticd::ik
