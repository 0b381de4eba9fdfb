#include "virtual_admittance.hpp"

#include <algorithm>
#include <cmath>

#include "hapticd/chain_state.hpp"
#include "hapticd/model/model_data.hpp"
#include "hapticd/render_port.hpp"

namespace hapticd::models {
namespace {

Eigen::Vector3d vector3(const std::vector<double>& v) { return {v[0], v[1], v[2]}; }

Eigen::Vector3d clamp_norm(const Eigen::Vector3d& v, double limit) noexcept {
  const double n = v.norm();
  return n > limit ? Eigen::Vector3d(v * (limit / n)) : v;
}

}  // namespace

ParameterSchema VirtualAdmittance::parameter_schema() {
  ParameterSchema s;
  // Sane bounds: below about 0.1 kg no inner loop renders a mass stably (the thesis's devices reach 0.4 kg at
  // best); a tiny value makes the body fly off and the device fault on speed.
  s.real_vector("mass_kg", "virtual mass along the world axes")
      .unit("kg")
      .size(3)
      .minimum(0.1)
      .maximum(1000.0)
      .default_value(std::vector<double>{5.0, 5.0, 5.0})
      .tunable();
  s.real_vector("damping_n_s_per_m", "virtual damping along the world axes")
      .unit("N s/m")
      .size(3)
      .minimum(0.0)
      .default_value(std::vector<double>{10.0, 10.0, 10.0})
      .tunable();
  s.boolean("rotation", "render rotations too (devices with actuated handle orientation)").default_value(true);
  s.real_vector("inertia_kg_m2", "virtual principal inertia about the handle axes")
      .unit("kg m^2")
      .size(3)
      .minimum(0.001)
      .maximum(100.0)
      .default_value(std::vector<double>{0.02, 0.02, 0.02})
      .tunable();
  s.real_vector("rotational_damping_n_m_s", "virtual rotational damping about the handle axes")
      .unit("N m s/rad")
      .size(3)
      .minimum(0.0)
      .default_value(std::vector<double>{0.1, 0.1, 0.1})
      .tunable();
  s.real_vector("walls",
                "virtual walls, 6 numbers each: a point on the wall and the normal pointing to the free "
                "side (world, m); at most 8")
      .default_value(std::vector<double>{});
  s.boolean("walls_relative", "wall points are offsets from the handle's position at activation").default_value(false);
  s.real("wall_stiffness_n_per_m", "stiffness of the walls")
      .unit("N/m")
      .minimum(0.0)
      .maximum(1e7)  // z-width sweeps go to 1e6 N/m (the device's own limits bound what it renders)
      .default_value(5000.0)
      .tunable();
  s.real("wall_damping_n_s_per_m", "damping of the walls while penetrated")
      .unit("N s/m")
      .minimum(0.0)
      .maximum(1e5)
      .default_value(50.0)
      .tunable();
  s.boolean("motion_based", "walls act on the measured handle motion (motion-based impedance control)")
      .default_value(false);
  s.boolean("coupling",
            "take the rendering engine's input: virtual coupling to its proxy pose, its wrench (and "
            "local model), or its desired motion")
      .default_value(false);
  // Physical maxima (a run-time set of 1e308 was taken before; the render guard bounded the force, not the gain).
  s.real("coupling_stiffness_n_per_m", "coupling spring")
      .unit("N/m")
      .minimum(0.0)
      .maximum(1e5)
      .default_value(2000.0)
      .tunable();
  s.real("coupling_damping_n_s_per_m", "coupling damper")
      .unit("N s/m")
      .minimum(0.0)
      .maximum(1e4)
      .default_value(20.0)
      .tunable();
  s.real("coupling_rotational_stiffness_n_m_per_rad", "rotational coupling spring")
      .unit("N m/rad")
      .minimum(0.0)
      .maximum(1e3)
      .default_value(20.0)
      .tunable();
  s.real("coupling_rotational_damping_n_m_s", "rotational coupling damper")
      .unit("N m s/rad")
      .minimum(0.0)
      .maximum(1e2)
      .default_value(0.2)
      .tunable();
  s.real("workspace_radius_m",
         "workspace spring: beyond this distance from the start position a spring pulls "
         "the body back; 0: off")
      .unit("m")
      .minimum(0.0)
      .default_value(0.0);
  s.real("workspace_stiffness_n_per_m", "stiffness of the workspace spring")
      .unit("N/m")
      .minimum(0.0)
      .maximum(1e5)
      .default_value(1000.0)
      .tunable();
  s.real("max_tracking_error_m",
         "anti-windup: while the drives saturate, the virtual body stays this close to the "
         "handle; 0: off")
      .unit("m")
      .minimum(0.0)
      .default_value(0.0);
  s.real("max_tracking_angle_rad", "anti-windup: the same for the orientation; 0: off")
      .unit("rad")
      .minimum(0.0)
      .default_value(0.0);
  s.real("max_velocity_m_s", "integration limit of the virtual speed").unit("m/s").greater_than(0.0).default_value(1.0);
  s.real("max_angular_velocity_rad_s", "integration limit of the virtual angular speed")
      .unit("rad/s")
      .greater_than(0.0)
      .default_value(5.0);
  s.real("engine_max_acceleration_m_s2",
         "an admittance-type engine's motion (MOTION commands) is followed with at most this acceleration and "
         "max_velocity_m_s: a jump in what the engine sends becomes a bounded motion")
      .unit("m/s^2")
      .greater_than(0.0)
      .maximum(1000.0)
      .default_value(10.0);
  s.real("engine_max_angular_acceleration_rad_s2", "the same for the orientation, with max_angular_velocity_rad_s")
      .unit("rad/s^2")
      .greater_than(0.0)
      .maximum(10000.0)
      .default_value(50.0);
  s.real("engine_joint_speed_fraction",
         "an engine's motion is followed at joint speeds of at most this share of each joint's velocity_max (the "
         "safety supervisor damps from 0.75 and faults at 0.95 of it); the Cartesian speed and acceleration limits "
         "shrink by the same factor where the joints would go faster")
      .minimum(0.05)
      .maximum(0.7)
      .default_value(0.5);
  s.real("engine_max_hand_force_n",
         "an engine's motion yields to the operator: from 3/4 of this force on the hand the body blends into its own "
         "dynamics (it moves with the hand), fully at this force; keep it below the rendered-force limit "
         "(safety.max_force_n, 80 N by default)")
      .unit("N")
      .greater_than(0.0)
      .maximum(1000.0)
      .default_value(50.0);
  return s;
}

void VirtualAdmittance::configure(const Parameters& p, const PluginContext& context) {
  if (context.device != nullptr && context.device->interface == DeviceInterface::handle &&
      !context.device->reports_wrench) {
    // Admittance display moves a virtual body with the operator's force; such a device cannot measure it.
    throw ParameterError("mass_kg", "device '" + context.device_name + "' (" + context.device->model +
                                        ") is a handle device without a force/torque sensor: the virtual "
                                        "admittance has no operator force to move with; render in impedance "
                                        "display (scripted_wrench with display: impedance, an engine's wrench)");
  }
  if (context.device == nullptr ||
      (context.device->robot_model_file.empty() && context.device->interface != DeviceInterface::handle) ||
      !context.device->reports_wrench) {
    throw ParameterError("mass_kg",
                         "the virtual admittance needs a device with a robot model and a force/torque sensor");
  }
  configure_environment(p, context);
}

void VirtualAdmittance::configure_environment(const Parameters& p, const PluginContext& context) {
  apply(tunable_of(p));
  rotation_ = p.boolean("rotation");
  max_velocity_ = p.real("max_velocity_m_s");
  max_angular_velocity_ = p.real("max_angular_velocity_rad_s");
  engine_max_acceleration_ = p.real("engine_max_acceleration_m_s2");
  engine_max_angular_acceleration_ = p.real("engine_max_angular_acceleration_rad_s2");
  engine_max_hand_force_ = p.real("engine_max_hand_force_n");
  const double share = p.real("engine_joint_speed_fraction");
  joint_count_ = 0;
  if (context.device != nullptr && context.device->interface == DeviceInterface::joints) {
    for (const JointDescription& j : context.device->joints) {
      if (joint_count_ == joint_speed_limit_.size()) break;
      joint_speed_limit_[joint_count_++] = share * j.velocity_max;
    }
  }
  period_s_ = 1.0 / context.rate_hz;
  const auto& w = p.real_vector("walls");
  if (w.size() % 6 != 0 || w.size() / 6 > kMaxWalls) {
    throw ParameterError("walls", "needs 6 numbers per wall (point, normal), at most " + std::to_string(kMaxWalls) +
                                      " walls; got " + std::to_string(w.size()) + " numbers");
  }
  wall_count_ = static_cast<int>(w.size() / 6);
  for (int i = 0; i < wall_count_; ++i) {
    const std::size_t o = static_cast<std::size_t>(6 * i);
    const Eigen::Vector3d normal(w[o + 3], w[o + 4], w[o + 5]);
    if (normal.norm() < 1e-9) throw ParameterError("walls", "wall " + std::to_string(i + 1) + " has a zero normal");
    walls_[static_cast<std::size_t>(i)] = Wall{Eigen::Vector3d(w[o], w[o + 1], w[o + 2]), normal.normalized()};
  }
  motion_based_ = p.boolean("motion_based");
  walls_relative_ = p.boolean("walls_relative");
  for (int i = 0; i < wall_count_; ++i)
    configured_wall_points_[static_cast<std::size_t>(i)] = walls_[static_cast<std::size_t>(i)].point;
  workspace_radius_ = p.real("workspace_radius_m");
  max_tracking_error_ = p.real("max_tracking_error_m");
  max_tracking_angle_ = p.real("max_tracking_angle_rad");
  coupling_ = p.boolean("coupling");
}

VirtualAdmittance::Tunable VirtualAdmittance::tunable_of(const Parameters& p) {
  Tunable t;
  t.mass = vector3(p.real_vector("mass_kg"));
  t.damping = vector3(p.real_vector("damping_n_s_per_m"));
  t.inertia = vector3(p.real_vector("inertia_kg_m2"));
  t.rotational_damping = vector3(p.real_vector("rotational_damping_n_m_s"));
  t.wall_k = p.real("wall_stiffness_n_per_m");
  t.wall_b = p.real("wall_damping_n_s_per_m");
  t.coupling_k = p.real("coupling_stiffness_n_per_m");
  t.coupling_b = p.real("coupling_damping_n_s_per_m");
  t.coupling_kr = p.real("coupling_rotational_stiffness_n_m_per_rad");
  t.coupling_br = p.real("coupling_rotational_damping_n_m_s");
  t.workspace_k = p.real("workspace_stiffness_n_per_m");
  return t;
}

void VirtualAdmittance::apply(const Tunable& t) noexcept {
  mass_ = t.mass;
  damping_ = t.damping;
  inertia_ = t.inertia;
  rotational_damping_ = t.rotational_damping;
  wall_stiffness_ = t.wall_k;
  wall_damping_ = t.wall_b;
  coupling_k_ = t.coupling_k;
  coupling_b_ = t.coupling_b;
  coupling_kr_ = t.coupling_kr;
  coupling_br_ = t.coupling_br;
  workspace_stiffness_ = t.workspace_k;
}

Eigen::Matrix<double, 6, 1> VirtualAdmittance::engine_wrench(const EngineInput& e, const Eigen::Vector3d& position,
                                                             const Eigen::Quaterniond& orientation,
                                                             const Eigen::Vector3d& velocity,
                                                             const Eigen::Vector3d& angular_velocity) const noexcept {
  Eigen::Matrix<double, 6, 1> w = Eigen::Matrix<double, 6, 1>::Zero();
  // The server fades stale input out (EngineInput::weight); motion input is followed, not felt as a wrench.
  if (!coupling_ || e.weight <= 0.0 || (!e.has_proxy && !e.has_wrench)) return w;
  if (e.has_proxy) {
    w.head<3>() = coupling_k_ * (e.proxy_pose.position - position) + coupling_b_ * (e.proxy_twist.linear - velocity);
    if (rotation_) {
      const Eigen::AngleAxisd error(e.proxy_pose.orientation.normalized() * orientation.conjugate());
      w.tail<3>() =
          coupling_kr_ * error.angle() * error.axis() + coupling_br_ * (e.proxy_twist.angular - angular_velocity);
    }
  }
  if (e.has_wrench) {
    w.head<3>() += e.wrench.force;
    if (rotation_) w.tail<3>() += e.wrench.torque;
    if (e.has_local_model) {
      // The engine's linearisation about its anchor, evaluated at loop rate between the engine's updates.
      w.head<3>() +=
          e.stiffness.head<3>().cwiseProduct(e.anchor.position - position) - e.damping.head<3>().cwiseProduct(velocity);
      if (rotation_) {
        const Eigen::AngleAxisd error(e.anchor.orientation.normalized() * orientation.conjugate());
        w.tail<3>() += e.stiffness.tail<3>().cwiseProduct(error.angle() * error.axis()) -
                       e.damping.tail<3>().cwiseProduct(angular_velocity);
      }
    }
  }
  return e.weight * w;
}

namespace {

// The velocity that heads for a target `error` away as fast as the limits allow and still stops there: along the
// error, at most the speed from which the acceleration limit stops it in time, and no more than it covers in
// one period (no overshoot).
Eigen::Vector3d approach_velocity(const Eigen::Vector3d& error, double max_acceleration, double dt) noexcept {
  const double distance = error.norm();
  if (!(distance > 0.0)) return Eigen::Vector3d::Zero();
  return std::min(std::sqrt(2.0 * max_acceleration * distance), distance / dt) * (error / distance);
}

}  // namespace

double VirtualAdmittance::joint_speed_scale(const ChainState& c, const Eigen::Vector3d& velocity) const noexcept {
  // The joint velocities that give the handle `velocity` (least squares through the translational Jacobian; near a
  // singularity they grow, and so does the cut), against each joint's share of its velocity_max.
  if (c.data == nullptr || joint_count_ == 0 || velocity.squaredNorm() < 1e-18) return 1.0;
  const auto& jacobian = c.data->frame_jacobian;
  const std::size_t n = std::min<std::size_t>(joint_count_, static_cast<std::size_t>(jacobian.cols()));
  const Eigen::Matrix3d jjt = jacobian.topRows<3>() * jacobian.topRows<3>().transpose();
  const Eigen::Vector3d y = (jjt + 1e-10 * Eigen::Matrix3d::Identity()).ldlt().solve(velocity);
  double worst = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double qd = jacobian.col(static_cast<Eigen::Index>(i)).head<3>().dot(y);
    if (joint_speed_limit_[i] > 0.0) worst = std::max(worst, std::abs(qd) / joint_speed_limit_[i]);
  }
  return std::isfinite(worst) && worst > 1.0 ? 1.0 / worst : (std::isfinite(worst) ? 1.0 : 0.0);
}

void VirtualAdmittance::follow_engine_motion(const EngineInput& e, std::int64_t now_ns, const BodyState& start,
                                             const ChainState& c) noexcept {
  // An admittance-type engine: the virtual body follows the engine's desired motion, extrapolated with its twist
  // since it arrived, from where the body was at the start of the cycle. It follows through a limiter - speed
  // (max_velocity_m_s) and acceleration (engine_max_acceleration_m_s2), both shrunk where the joints would pass
  // engine_joint_speed_fraction of their velocity_max - so whatever the engine sends, a jump of its target
  // included, the inner loop is given a motion the device can make (a jump passed straight on was chased at full
  // torque into the speed limit's fault; a Cartesian limit alone let the joints pass theirs). It yields to the
  // operator: above 3/4 of engine_max_hand_force_n on the hand the body blends into its own dynamics, which move it
  // with the hand (a far target pulled the hand with 140 N before). While the input fades, the body blends back to
  // its own dynamics from where it is.
  const double dt = period_s_;
  const double since = std::max(0.0, static_cast<double>(now_ns - e.received_ns) * 1e-9);
  const Eigen::Vector3d desired = e.motion_pose.position + since * e.motion_twist.linear;
  const double joints = joint_speed_scale(c, desired - start.position);
  const double speed = max_velocity_ * joints, acceleration = engine_max_acceleration_ * joints;
  const Eigen::Vector3d wanted = clamp_norm(
      clamp_norm(e.motion_twist.linear, speed) + approach_velocity(desired - start.position, acceleration, dt), speed);
  Eigen::Vector3d followed_velocity =
      clamp_norm(start.velocity + clamp_norm(wanted - start.velocity, acceleration * dt), max_velocity_);
  followed_velocity *= joint_speed_scale(c, followed_velocity);
  const Eigen::Vector3d followed_position = start.position + dt * followed_velocity;
  const double hand = c.has_operator_wrench ? c.operator_wrench.force.norm() : 0.0;
  const double yield = std::clamp((engine_max_hand_force_ - hand) / (0.25 * engine_max_hand_force_), 0.0, 1.0);
  hand_yield_ = std::min(yield, hand_yield_ + dt / 0.1);  // yields at once, takes up the motion again over 0.1 s
  const double a = e.weight * hand_yield_;
  position_ = (1.0 - a) * position_ + a * followed_position;
  velocity_ = clamp_norm((1.0 - a) * velocity_ + a * followed_velocity, max_velocity_);
  if (rotation_) {
    const double angle = e.motion_twist.angular.norm() * since;
    Eigen::Quaterniond q = e.motion_pose.orientation.normalized();
    if (angle > 0.0) q = Eigen::Quaterniond(Eigen::AngleAxisd(angle, e.motion_twist.angular.normalized())) * q;
    // The same limiter on the rotation: the error as a rotation vector in world axes.
    const Eigen::AngleAxisd error(q * start.orientation.conjugate());
    const Eigen::Vector3d error_vector = error.angle() * error.axis();
    const Eigen::Vector3d start_world = start.orientation * start.body_angular_velocity;
    const Eigen::Vector3d wanted_w =
        clamp_norm(clamp_norm(e.motion_twist.angular, max_angular_velocity_) +
                       approach_velocity(error_vector, engine_max_angular_acceleration_, dt),
                   max_angular_velocity_);
    const Eigen::Vector3d followed_w = clamp_norm(
        start_world + clamp_norm(wanted_w - start_world, engine_max_angular_acceleration_ * dt), max_angular_velocity_);
    Eigen::Quaterniond followed = start.orientation;
    const double step = followed_w.norm() * dt;
    if (step > 0.0) followed = (Eigen::Quaterniond(Eigen::AngleAxisd(step, followed_w.normalized())) * followed);
    orientation_ = orientation_.slerp(a, followed.normalized()).normalized();
    const Eigen::Vector3d body = orientation_.conjugate() * followed_w;
    body_angular_velocity_ = clamp_norm((1.0 - a) * body_angular_velocity_ + a * body, max_angular_velocity_);
  }
}

Eigen::Vector3d VirtualAdmittance::wall_force(const Eigen::Vector3d& position,
                                              const Eigen::Vector3d& velocity) const noexcept {
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (int i = 0; i < wall_count_; ++i) {
    const Wall& w = walls_[static_cast<std::size_t>(i)];
    const double depth = -(position - w.point).dot(w.normal);  // > 0 inside the wall
    if (depth <= 0.0) continue;
    // Unilateral: the wall pushes, never pulls.
    const double push = wall_stiffness_ * depth - wall_damping_ * velocity.dot(w.normal);
    if (push > 0.0) f += push * w.normal;
  }
  if (workspace_radius_ > 0.0) {  // a soft spherical workspace limit around the start position
    const Eigen::Vector3d from_centre = position - workspace_centre_;
    const double beyond = from_centre.norm() - workspace_radius_;
    if (beyond > 0.0) f -= workspace_stiffness_ * beyond * from_centre.normalized();
  }
  return f;
}

bool VirtualAdmittance::limit_tracking_error(const ChainState& c) noexcept {
  bool limited = false;
  if (max_tracking_error_ > 0.0) {
    const Eigen::Vector3d error = position_ - c.handle_pose.position;
    const double distance = error.norm();
    // Only a body running ahead of a device that cannot follow is held back; a body behind the handle is the
    // controller braking a pushed device, which must go on.
    if (distance > max_tracking_error_ && velocity_.dot(error) > 0.0) {
      const Eigen::Vector3d direction = error / distance;
      position_ = c.handle_pose.position + max_tracking_error_ * direction;
      const double away = velocity_.dot(direction) - c.handle_twist.linear.dot(direction);
      if (away > 0.0) velocity_ -= away * direction;  // no faster away from the handle than the handle itself
      limited = true;
    }
  }
  if (rotation_ && max_tracking_angle_ > 0.0) {
    const Eigen::Quaterniond handle = c.handle_pose.orientation.normalized();
    const Eigen::AngleAxisd error(orientation_ * handle.conjugate());
    if (error.angle() > max_tracking_angle_) {
      orientation_ = (Eigen::Quaterniond(Eigen::AngleAxisd(max_tracking_angle_, error.axis())) * handle).normalized();
      const Eigen::Vector3d axis_body = orientation_.conjugate() * error.axis();
      const double away = body_angular_velocity_.dot(axis_body) - c.handle_twist.angular.dot(error.axis());
      if (away > 0.0) body_angular_velocity_ -= away * axis_body;
    }
  }
  return limited;
}

void VirtualAdmittance::tune(const Parameters& parameters) { tunable_inbox_.publish(tunable_of(parameters)); }

Outcome VirtualAdmittance::activate(const VirtualModelInput& current) {
  if (!current.chain.has_handle)
    return Outcome::failure("the virtual admittance needs the handle's pose: a robot model or a handle device");
  // Start where the handle is, moving as it moves: no jump in the desired motion.
  position_ = current.chain.handle_pose.position;
  workspace_centre_ = position_;
  for (int i = 0; i < wall_count_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    walls_[k].point =
        walls_relative_ ? Eigen::Vector3d(configured_wall_points_[k] + position_) : configured_wall_points_[k];
  }
  velocity_ = clamp_norm(current.chain.handle_twist.linear, max_velocity_);
  orientation_ = current.chain.handle_pose.orientation.normalized();
  body_angular_velocity_ = rotation_ ? Eigen::Vector3d(orientation_.conjugate() * current.chain.handle_twist.angular)
                                     : Eigen::Vector3d::Zero();
  return Outcome::success();
}

Outcome VirtualAdmittance::update(const CycleTime& cycle, const VirtualModelInput& input, TaskTarget& target) {
  return update(cycle, input, target, Eigen::Matrix<double, 6, 1>::Zero());
}

Outcome VirtualAdmittance::update(const CycleTime& cycle, const VirtualModelInput& input, TaskTarget& target,
                                  const Eigen::Matrix<double, 6, 1>& scripted) {
  const ChainState& c = input.chain;
  const double dt = period_s_;
  take_tuning();  // run-time parameters, at a cycle boundary
  const Eigen::Vector3d world_angular = orientation_ * body_angular_velocity_;
  const EngineInput& e = input.engine;
  const BodyState start{position_, velocity_, body_angular_velocity_, orientation_};
  // The port where the engine acts: the handle (motion-based) or the virtual body.
  Eigen::Matrix<double, 6, 1> port_twist;
  if (motion_based_) {
    port_twist << c.handle_twist.linear, c.handle_twist.angular;
  } else {
    port_twist << velocity_, world_angular;
  }
  Eigen::Matrix<double, 6, 1> engine = motion_based_
                                           ? engine_wrench(e, c.handle_pose.position, c.handle_pose.orientation,
                                                           c.handle_twist.linear, c.handle_twist.angular)
                                           : engine_wrench(e, position_, orientation_, velocity_, world_angular);
  // The safety layer: passivity controller on the engine port, then the rendered-wrench limits.
  engine = input.render.engine_port(engine, port_twist);
  Eigen::Matrix<double, 6, 1> rendered;
  rendered << engine.head<3>() + scripted.head<3>() +
                  (motion_based_ ? wall_force(c.handle_pose.position, c.handle_twist.linear)
                                 : wall_force(position_, velocity_)),
      rotation_ ? Eigen::Vector3d(engine.tail<3>() + scripted.tail<3>()) : Eigen::Vector3d::Zero();
  rendered = input.render.limit(rendered);
  // The safety supervisor's walls and speed damping act on the virtual body too (after the limits: they are not
  // the environment's), so the inner loop follows them instead of fighting them.
  rendered.head<3>() += input.render.take_safety_force();
  const Eigen::Vector3d environment = rendered.head<3>();
  const Eigen::Vector3d force = c.operator_wrench.force + environment;
  const Eigen::Vector3d acceleration = (force - damping_.cwiseProduct(velocity_)).cwiseQuotient(mass_);
  velocity_ = clamp_norm(velocity_ + dt * acceleration, max_velocity_);
  position_ += dt * velocity_;

  Eigen::Vector3d angular_acceleration_world = Eigen::Vector3d::Zero();
  if (rotation_) {
    const Eigen::Vector3d torque_body = orientation_.conjugate() * (c.operator_wrench.torque + rendered.tail<3>());
    const Eigen::Vector3d& w = body_angular_velocity_;
    const Eigen::Vector3d wd =
        (torque_body - w.cross(inertia_.cwiseProduct(w)) - rotational_damping_.cwiseProduct(w)).cwiseQuotient(inertia_);
    body_angular_velocity_ = clamp_norm(w + dt * wd, max_angular_velocity_);
    // Exact rotation over the step for the body-frame angular velocity.
    const double angle = body_angular_velocity_.norm() * dt;
    if (angle > 0.0) {
      orientation_ = (orientation_ * Eigen::Quaterniond(Eigen::AngleAxisd(angle, body_angular_velocity_.normalized())))
                         .normalized();
    }
    angular_acceleration_world = orientation_ * wd;
  }
  if (coupling_ && e.has_motion && e.weight > 0.0) follow_engine_motion(e, cycle.time_ns, start, c);
  Eigen::Vector3d commanded_acceleration = acceleration;
  if (c.output_saturated && limit_tracking_error(c)) {
    // On the limit: no acceleration away from the handle either (the inner loop gets a consistent target).
    const Eigen::Vector3d away = (position_ - c.handle_pose.position).normalized();
    const double outward = commanded_acceleration.dot(away);
    if (outward > 0.0) commanded_acceleration -= outward * away;
  }
  target.pose.position = position_;
  target.pose.orientation = rotation_ ? orientation_ : c.handle_pose.orientation;
  target.twist.linear = velocity_;
  target.twist.angular = rotation_ ? Eigen::Vector3d(orientation_ * body_angular_velocity_) : Eigen::Vector3d::Zero();
  target.acceleration.linear = commanded_acceleration;
  target.acceleration.angular = angular_acceleration_world;
  target.wrench.force = environment;  // what the environment applies to the handle
  target.wrench.torque = rendered.tail<3>();
  target.has_motion = true;
  target.has_wrench = false;
  return Outcome::success();
}

}  // namespace hapticd::models
