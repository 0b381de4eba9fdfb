#include "sim_device.hpp"

#include <cmath>
#include <stdexcept>

#include "hapticd/model/kinematics.hpp"
#include "hapticd/model/urdf_loader.hpp"
#include "physics_builder.hpp"

namespace hapticd::sim {
namespace {

const std::vector<std::string> kProfiles{"constant", "step", "ramp", "sine", "shuttle"};

void declare_profile(ParameterSchema& s, const std::string& prefix, const std::string& what, const std::string& unit,
                     const std::string& default_kind) {
  s.string(prefix, what +
                       ": constant, step (at _start_s), ramp (value per second), sine (amplitude) or shuttle (out "
                       "along the value and back, trapezoidal velocity: _acceleration, _speed)")
      .choices(kProfiles)
      .default_value(default_kind);
  // The name's unit suffix as the unit it stands for.
  const std::string si = unit == "n" ? "N" : unit == "nm" ? "N m" : unit;
  s.real_vector(prefix + "_" + unit, what + " value (x, y, z, world)")
      .unit(si)
      .size(3)
      .default_value(std::vector<double>{0, 0, 0});
  s.real(prefix + "_start_s", what + ": start of the step, ramp or sine").unit("s").minimum(0.0).default_value(0.0);
  s.real(prefix + "_frequency_hz", what + ": frequency of the sine").unit("Hz").greater_than(0.0).default_value(0.5);
  s.real(prefix + "_acceleration", what + ": acceleration of the shuttle's constant-acceleration phases (per s^2)")
      .greater_than(0.0)
      .default_value(1.0);
  s.real(prefix + "_speed", what + ": speed of the shuttle's constant-velocity phases (per s)")
      .greater_than(0.0)
      .default_value(0.1);
}

// Defaults: the attachment's own (handle_attachment.hpp).
void declare_grasp_range(ParameterSchema& s, const std::string& name, const std::string& what, const std::string& unit,
                         const GraspRange& defaults) {
  s.real_vector(name, what + ", loose and firm (geometric between)")
      .size(2)
      .unit(unit)
      .greater_than(0.0)
      .default_value(std::vector<double>{defaults.loose, defaults.firm});
}

GraspRange read_grasp_range(const Parameters& p, const std::string& name) {
  const auto& v = p.real_vector(name);
  return {v[0], v[1]};
}

Profile read_profile(const Parameters& p, const std::string& prefix, const std::string& unit) {
  Profile profile;
  profile.kind = Profile::parse(p.string(prefix));
  const auto& v = p.real_vector(prefix + "_" + unit);
  profile.value = Eigen::Vector3d(v[0], v[1], v[2]);
  profile.start_s = p.real(prefix + "_start_s");
  profile.frequency_hz = p.real(prefix + "_frequency_hz");
  profile.acceleration = p.real(prefix + "_acceleration");
  profile.speed = p.real(prefix + "_speed");
  return profile;
}

AttachmentKind parse_attachment(const std::string& name) {
  if (name == "operator") return AttachmentKind::operator_hand;
  if (name == "position_source") return AttachmentKind::position_source;
  if (name == "wrench") return AttachmentKind::wrench;
  return AttachmentKind::none;
}

}  // namespace

ParameterSchema SimDevice::parameter_schema() {
  ParameterSchema s;
  s.string("urdf", "robot model with <hapticd_drive> data (relative paths: from the session file's folder)");
  s.string("handle_frame", "frame of the handle (end-effector) in the model").default_value(std::string("handle"));
  s.string("sensor_frame", "frame of the force/torque sensor; empty: no sensor").default_value(std::string("sensor"));
  s.boolean("passive_gimbal", "the handle turns freely (ViSHaRD3's thimble): attachments apply no torques")
      .default_value(false);
  s.real_vector("initial_position", "joint positions at activation; empty: all zero")
      .default_value(std::vector<double>{});
  s.real("substep_hz", "physics integration rate").unit("Hz").minimum(2000.0).maximum(1e6).default_value(20000.0);
  s.real("rigid_body_hz",
         "rate of the rigid-body terms (mass matrix, Coriolis and gravity, the handle's Jacobian; the drive springs, "
         "motors and friction run at substep_hz), rounded to a whole number of substeps; 0 or substep_hz and "
         "above: single-rate (docs/simulated-devices.md)")
      .unit("Hz")
      .minimum(0.0)
      .maximum(1e6)
      .default_value(4000.0);
  s.real("structural_damping_ratio",
         "damping ratio of each drive's spring (the gear's hysteresis); -1: the model's drive damping_ratio "
         "where it gives one (ViSHaRD3: 0.15, calibrated, docs/evaluation.md), else 0.02")
      .minimum(-1.0)
      .maximum(1.0)
      .default_value(-1.0);
  s.boolean("friction", "master switch of all gear friction").default_value(true);
  s.boolean("sliding_friction", "Coulomb and viscous (Stribeck curve) friction").default_value(true);
  s.boolean("stiction", "stiction with a random break-away level per sticking").default_value(true);
  s.boolean("load_friction", "friction rising with the transmitted torque").default_value(true);
  s.boolean("warm_up", "friction drifts from the 26 C to the 36 C curve").default_value(true);
  s.real("warm_up_time_constant_s", "time constant of the warm-up").unit("s").greater_than(0.0).default_value(600.0);
  s.real("friction_variation", "relative standard deviation of the per-joint friction scale")
      .minimum(0.0)
      .maximum(0.5)
      .default_value(0.1);
  s.boolean("ripple", "position-dependent torque ripple, 2 cycles per motor revolution").default_value(true);
  s.boolean("current_loop", "first-order current loop (else the torque is applied at once)").default_value(true);
  s.real("current_bandwidth_hz", "current-loop bandwidth").unit("Hz").greater_than(0.0).default_value(2500.0);
  s.real("command_delay_s",
         "dead time from write() to the torque reaching the current loop (computation, bus, PWM update); "
         "rounded to substeps")
      .unit("s")
      .minimum(0.0)
      .maximum(0.004)
      .default_value(0.0);
  s.boolean("structural_compliance",
            "the structure's compliance in series with each gear (the model's structural_stiffness; "
            "docs/evaluation.md)")
      .default_value(true);
  s.boolean("thermal_limit", "limit to the continuous torque while the winding is hot").default_value(true);
  s.real("thermal_time_constant_s", "winding time constant").unit("s").greater_than(0.0).default_value(30.0);
  s.real("current_offset_nm", "amplifier current offset, as a joint torque").unit("N m").default_value(0.0);
  s.boolean("speed_monitor", "a joint above its speed limit faults the device (latched until a fault reset)")
      .default_value(true);
  s.boolean("homing",
            "incremental encoders: until homing finds their index, positions are relative to where the device "
            "was enabled and read() reports the device not homed (the server homes it at start)")
      .default_value(false);
  s.boolean("brakes",
            "holding brakes: engaged while the drives are off (before enable, after disable: the simulation "
            "holds still), released by enable")
      .default_value(false);
  s.boolean("joint_torque_sensors",
            "each joint measures its output torque (the gear spring's); effort is the "
            "drive torque otherwise")
      .default_value(false);
  s.real("joint_torque_resolution_nm", "resolution of the joint torque sensors")
      .unit("N m")
      .greater_than(0.0)
      .default_value(0.01);
  s.boolean("encoder_quantisation", "positions in whole encoder counts (motor side)").default_value(true);
  s.real_vector("sensor_force_range_n", "force ranges of the sensor")
      .unit("N")
      .size(3)
      .minimum(0.0)
      .default_value(std::vector<double>{200, 200, 400});
  s.real_vector("sensor_torque_range_nm", "torque ranges of the sensor")
      .unit("N m")
      .size(3)
      .minimum(0.0)
      .default_value(std::vector<double>{12, 12, 12});
  s.real("sensor_noise_lsb", "sensor noise standard deviation, in resolution steps (1/4000 of the range)")
      .minimum(0.0)
      .default_value(0.5);
  s.real("sensor_bandwidth_hz", "sensor bandwidth").unit("Hz").greater_than(0.0).default_value(8000.0);
  s.boolean("sensor_handle_inertia",
            "the sensor reads the inertial force of what it carries (the URDF's links beyond the sensor frame: "
            "handle, gimbal) besides their weight; false: their weight only")
      .default_value(true);
  s.boolean("sensor_accelerations", "the sensor also measures linear and angular acceleration (ViSHaRD3's JR3)")
      .default_value(false);
  s.real_vector("sensor_acceleration_range", "ranges of the linear [m/s^2] and angular [rad/s^2] acceleration")
      .size(2)
      .greater_than(0.0)
      .default_value(std::vector<double>{49.0, 100.0});
  s.real_vector("sensor_acceleration_resolution", "resolution of the linear and angular acceleration")
      .size(2)
      .greater_than(0.0)
      .default_value(std::vector<double>{0.0981, 0.1});
  s.string("attachment", "what holds the handle at activation")
      .choices({"none", "operator", "position_source", "wrench"})
      .default_value(std::string("none"));
  s.real("operator_grasp", "operator's grasp, 0 loose .. 1 firm").minimum(0.0).maximum(1.0).default_value(0.5);
  s.real("operator_hand_mass_kg", "operator's hand-arm mass").unit("kg").greater_than(0.0).default_value(1.5);
  declare_grasp_range(s, "operator_grasp_stiffness", "operator's grasp stiffness", "N/m",
                      AttachmentSettings{}.grasp_stiffness);
  declare_grasp_range(s, "operator_grasp_damping", "operator's grasp damping", "N s/m",
                      AttachmentSettings{}.grasp_damping);
  s.real("operator_arm_stiffness", "operator's arm stiffness towards the target motion")
      .unit("N/m")
      .minimum(0.0)
      .default_value(300.0);
  s.real("operator_arm_damping", "operator's arm damping").unit("N s/m").minimum(0.0).default_value(25.0);
  declare_profile(s, "operator_motion", "operator's target motion from the grasp position", "m", "constant");
  declare_profile(s, "operator_force", "operator's voluntary force", "n", "constant");
  s.real("operator_hand_inertia_kg_m2", "operator's hand rotational inertia (about every axis)")
      .unit("kg m^2")
      .greater_than(0.0)
      .default_value(0.005);
  declare_grasp_range(s, "operator_grasp_rotational_stiffness", "operator's grasp rotational stiffness", "N m/rad",
                      AttachmentSettings{}.grasp_rotational_stiffness);
  declare_grasp_range(s, "operator_grasp_rotational_damping", "operator's grasp rotational damping", "N m s/rad",
                      AttachmentSettings{}.grasp_rotational_damping);
  s.real("operator_arm_rotational_stiffness", "operator's arm stiffness towards the target rotation")
      .unit("N m/rad")
      .minimum(0.0)
      .default_value(5.0);
  s.real("operator_arm_rotational_damping", "operator's arm rotational damping")
      .unit("N m s/rad")
      .minimum(0.0)
      .default_value(0.2);
  declare_profile(s, "operator_rotation", "operator's target rotation from the grasp orientation (rotation vector)",
                  "rad", "constant");
  declare_profile(s, "operator_torque", "operator's voluntary torque", "nm", "constant");
  s.real("source_stiffness", "position source coupling stiffness").unit("N/m").greater_than(0.0).default_value(1e5);
  s.real("source_damping", "position source coupling damping").unit("N s/m").minimum(0.0).default_value(500.0);
  declare_profile(s, "source_path", "position source path from the attach position", "m", "constant");
  declare_profile(s, "wrench_force", "scripted force", "n", "constant");
  declare_profile(s, "wrench_torque", "scripted torque", "nm", "constant");
  s.real_vector("wall_normal",
                "a wall in the device's world: the direction from the handle's position at enable towards it (world); "
                "zero: no wall")
      .size(3)
      .default_value(std::vector<double>{0.0, 0.0, 0.0});
  s.real("wall_offset_m", "the wall's distance along wall_normal from the handle's position at enable")
      .unit("m")
      .minimum(0.0)
      .maximum(1.0)
      .default_value(WallSettings{}.offset_m);
  s.real("wall_stiffness", "the wall's stiffness")
      .unit("N/m")
      .greater_than(0.0)
      .maximum(1e6)
      .default_value(WallSettings{}.stiffness);
  s.real("wall_damping", "the wall's damping (it pushes, never pulls)")
      .unit("N s/m")
      .minimum(0.0)
      .maximum(1e4)
      .default_value(WallSettings{}.damping);
  s.real("wall_contact_half_width_m",
         "0: the handle touches the wall at its point; else with a square plate of this half width that turns with "
         "the handle (four corners, a quarter of the wall's spring-damper each): a tilt is turned back too")
      .unit("m")
      .minimum(0.0)
      .maximum(0.2)
      .default_value(WallSettings{}.contact_half_width_m);
  return s;
}

void SimDevice::configure(const Parameters& p, const PluginContext& context) {
  std::filesystem::path urdf = p.string("urdf");
  if (urdf.is_relative()) urdf = context.config_directory / urdf;
  // Placed where the session puts the device: its physics (gravity, the operator's and the source's forces) in the
  // world frame, as the server's model of it.
  model::RobotModel robot = [&] {
    try {
      return model::load_robot_model(urdf).with_base(to_isometry(context.base_pose));
    } catch (const model::ModelError& e) {
      throw ParameterError("urdf", e.what());
    }
  }();
  const int n = robot.dof();
  handle_frame_ = robot.frame_id(p.string("handle_frame"));
  if (handle_frame_ < 0)
    throw ParameterError("handle_frame", "no frame '" + p.string("handle_frame") + "' in " + urdf.string());
  sensor_present_ = !p.string("sensor_frame").empty();
  sensor_frame_ = sensor_present_ ? robot.frame_id(p.string("sensor_frame")) : -1;
  if (sensor_present_ && sensor_frame_ < 0) {
    throw ParameterError("sensor_frame", "no frame '" + p.string("sensor_frame") + "' in " + urdf.string());
  }
  const auto& q0 = p.real_vector("initial_position");
  if (!q0.empty() && static_cast<int>(q0.size()) != n) {
    throw ParameterError("initial_position", "needs " + std::to_string(n) + " values (the model's joints), got " +
                                                 std::to_string(q0.size()));
  }
  initial_position_ = JointVector::Zero(n);
  for (int i = 0; i < static_cast<int>(q0.size()); ++i) initial_position_[i] = q0[static_cast<std::size_t>(i)];

  PhysicsOptions physics;
  physics.damping_ratio = p.real("structural_damping_ratio");
  physics.friction = p.boolean("friction");
  physics.friction_template.sliding = p.boolean("sliding_friction");
  physics.friction_template.stiction = p.boolean("stiction");
  physics.friction_template.load_dependent = p.boolean("load_friction");
  physics.friction_template.warm_up = p.boolean("warm_up");
  physics.friction_template.warm_up_time_constant_s = p.real("warm_up_time_constant_s");
  physics.friction_variation = p.real("friction_variation");
  physics.ripple = p.boolean("ripple");
  physics.structural_compliance = p.boolean("structural_compliance");
  try {
    chain_ = std::make_unique<FlexibleChain>(build_flexible_chain(robot, handle_frame_, physics, context.seed));
  } catch (const std::invalid_argument& e) {
    throw ParameterError("urdf", e.what());
  }

  substep_ns_ = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::llround(1e9 / p.real("substep_hz"))));
  const std::int64_t period_ns = static_cast<std::int64_t>(std::llround(1e9 / context.rate_hz));
  if (period_ns % substep_ns_ != 0) {
    throw ParameterError("substep_hz", "must divide the control period evenly (a multiple of the rate " +
                                           std::to_string(context.rate_hz) + " Hz)");
  }
  substep_s_ = static_cast<double>(substep_ns_) * 1e-9;
  const double rigid_body_hz = p.real("rigid_body_hz");
  if (rigid_body_hz > 0.0)
    chain_->set_rigid_body_every(static_cast<int>(std::max(1L, std::lround(p.real("substep_hz") / rigid_body_hz))));
  chain_->reset(initial_position_);
  const double highest = chain_->highest_frequency();
  if (highest * substep_s_ > 0.5) {
    throw ParameterError("substep_hz", "the stiffest joint oscillates at " + std::to_string(highest / (2 * M_PI)) +
                                           " Hz: at least " + std::to_string(highest / 0.5) +
                                           " Hz of substeps are needed for a stable integration");
  }

  drives_.assign(static_cast<std::size_t>(n), Drive{});
  counts_per_rev_.resize(n);
  description_ = DeviceDescription{};
  description_.model = robot.name();
  for (int i = 0; i < n; ++i) {
    const model::Body& b = robot.body(i);
    DriveParameters d;
    d.peak_torque = b.drive.peak_joint_torque();
    d.continuous_torque = b.drive.continuous_joint_torque();
    d.current_bandwidth_hz = p.real("current_bandwidth_hz");
    d.thermal_time_constant_s = p.real("thermal_time_constant_s");
    d.current_offset_nm = p.real("current_offset_nm");
    d.current_loop = p.boolean("current_loop");
    d.thermal_limit = p.boolean("thermal_limit");
    drives_[static_cast<std::size_t>(i)].configure(d);
    counts_per_rev_[i] = p.boolean("encoder_quantisation") ? b.drive.joint_counts_per_rev() : 0.0;
    description_.joints.push_back(JointDescription{b.joint_name, b.position_min, b.position_max,
                                                   b.drive.max_joint_speed(), d.peak_torque, d.continuous_torque});
  }
  speed_limits_ = robot.speed_limits();
  speed_monitor_ = p.boolean("speed_monitor");
  description_.capabilities.homing = p.boolean("homing");
  description_.capabilities.brakes = p.boolean("brakes");
  description_.handle_frame = p.string("handle_frame");
  description_.sensor_frame = p.string("sensor_frame");
  description_.robot_model_file = urdf.string();
  description_.simulated = true;
  description_.reports_wrench = sensor_present_;
  joint_torque_sensors_ = p.boolean("joint_torque_sensors");
  joint_torque_resolution_ = p.real("joint_torque_resolution_nm");
  description_.reports_joint_torque = joint_torque_sensors_;

  ForceSensorParameters sensor;
  const auto& fr = p.real_vector("sensor_force_range_n");
  const auto& tr = p.real_vector("sensor_torque_range_nm");
  sensor.range << fr[0], fr[1], fr[2], tr[0], tr[1], tr[2];
  sensor.noise_lsb = p.real("sensor_noise_lsb");
  sensor.bandwidth_hz = p.real("sensor_bandwidth_hz");
  sensor_.configure(sensor, context.seed ^ 0x5EB5EB5EULL);
  if (sensor_present_) {
    carried_mass_ = robot.frame(sensor_frame_).carried_mass;
    carried_com_ = robot.frame(sensor_frame_).carried_com;
  }
  carried_inertia_ = p.boolean("sensor_handle_inertia");
  accelerations_ = sensor_present_ && p.boolean("sensor_accelerations");
  description_.reports_sensor_acceleration = accelerations_;
  const auto& ar = p.real_vector("sensor_acceleration_range");
  const auto& aq = p.real_vector("sensor_acceleration_resolution");
  acceleration_range_ = {ar[0], ar[1]};
  acceleration_resolution_ = {aq[0], aq[1]};

  AttachmentSettings a;
  a.kind = parse_attachment(p.string("attachment"));
  a.grasp = p.real("operator_grasp");
  a.hand_mass_kg = p.real("operator_hand_mass_kg");
  a.grasp_stiffness = read_grasp_range(p, "operator_grasp_stiffness");
  a.grasp_damping = read_grasp_range(p, "operator_grasp_damping");
  a.arm_stiffness = p.real("operator_arm_stiffness");
  a.arm_damping = p.real("operator_arm_damping");
  a.motion = read_profile(p, "operator_motion", "m");
  a.force = read_profile(p, "operator_force", "n");
  a.hand_inertia_kg_m2 = p.real("operator_hand_inertia_kg_m2");
  a.grasp_rotational_stiffness = read_grasp_range(p, "operator_grasp_rotational_stiffness");
  a.grasp_rotational_damping = read_grasp_range(p, "operator_grasp_rotational_damping");
  a.arm_rotational_stiffness = p.real("operator_arm_rotational_stiffness");
  a.arm_rotational_damping = p.real("operator_arm_rotational_damping");
  a.rotation = read_profile(p, "operator_rotation", "rad");
  a.torque = read_profile(p, "operator_torque", "nm");
  a.source_stiffness = p.real("source_stiffness");
  a.source_damping = p.real("source_damping");
  a.path = read_profile(p, "source_path", "m");
  a.wrench_force = read_profile(p, "wrench_force", "n");
  a.wrench_torque = read_profile(p, "wrench_torque", "nm");
  initial_attachment_ = a;
  requested_ = a;
  WallSettings wall;
  const auto& wn = p.real_vector("wall_normal");
  const Eigen::Vector3d normal(wn[0], wn[1], wn[2]);
  if (!normal.allFinite()) throw ParameterError("wall_normal", "must be finite");
  if (normal.norm() > 0.0) {
    if (normal.norm() < 1e-6) throw ParameterError("wall_normal", "zero (no wall) or a direction");
    wall.normal = normal.normalized();
  }
  wall.offset_m = p.real("wall_offset_m");
  wall.stiffness = p.real("wall_stiffness");
  wall.damping = p.real("wall_damping");
  wall.contact_half_width_m = p.real("wall_contact_half_width_m");
  wall_.configure(wall);
  passive_gimbal_ = p.boolean("passive_gimbal");

  command_ = JointVector::Zero(n);
  truth_.motor_torque = JointVector::Zero(n);
  command_delay_ns_ = substep_ns_ * std::llround(p.real("command_delay_s") * 1e9 / static_cast<double>(substep_ns_));
  if (command_delay_ns_ >= static_cast<std::int64_t>(kMaxDelayed - 1) * period_ns) {
    throw ParameterError("command_delay_s", "at most " + std::to_string(kMaxDelayed - 2) + " control periods");
  }
  for (DelayedCommand& d : delayed_) d.torque = JointVector::Zero(n);
}

Outcome SimDevice::enable() {
  enabled_ = true;
  homed_ = !description_.capabilities.homing;
  chain_->reset(initial_position_);
  for (Drive& d : drives_) d.reset();
  sensor_.reset();
  carried_velocity_valid_ = false;
  attachment_.select(initial_attachment_);
  wall_.reset();
  command_.setZero();
  delayed_count_ = 0;
  simulated_ns_ = 0;
  truth_.overspeed_joint = -1;
  chain_->prepare();
  truth_.handle_pose = chain_->handle_pose();
  truth_.handle_twist.setZero();
  truth_.handle_wrench.setZero();
  truth_.sensor_wrench.setZero();
  truth_.link_position = chain_->link_position();
  truth_.motor_position = chain_->motor_position();
  encoder_offset_ = homed_ ? JointVector::Zero(chain_->dof()) : JointVector(chain_->motor_position());
  return Outcome::success();
}

void SimDevice::apply_due_commands() noexcept {
  while (delayed_count_ > 0 && delayed_[delayed_head_].due_ns <= simulated_ns_) {
    command_ = delayed_[delayed_head_].torque;
    delayed_head_ = (delayed_head_ + 1) % kMaxDelayed;
    --delayed_count_;
  }
}

void SimDevice::sensor_reading(const Eigen::Isometry3d& handle, const Vector6d& twist,
                               const Vector6d& wrench) noexcept {
  // The sensor reads the force and moment (about its origin) with which what it carries pulls on it: the
  // external wrench at the handle plus the carried mass's weight minus its inertial force, m (g - a).
  const Eigen::Isometry3d s = chain_->carried_frame_pose(sensor_frame_);
  Eigen::Vector3d force = wrench.head<3>();
  Eigen::Vector3d moment = wrench.tail<3>() + (handle.translation() - s.translation()).cross(force);
  if (carried_mass_ > 0.0) {
    const Eigen::Vector3d centre = s * carried_com_;
    const Eigen::Vector3d velocity = twist.head<3>() + twist.tail<3>().cross(centre - handle.translation());
    Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();
    if (carried_inertia_ && carried_velocity_valid_) acceleration = (velocity - carried_velocity_) / substep_s_;
    carried_velocity_ = velocity;
    carried_velocity_valid_ = true;
    const Eigen::Vector3d load = carried_mass_ * (chain_->link_model().gravity() - acceleration);
    force += load;
    moment += (centre - s.translation()).cross(load);
  }
  const Eigen::Matrix3d rt = s.linear().transpose();
  Vector6d at_sensor;
  at_sensor.head<3>() = rt * force;
  at_sensor.tail<3>() = rt * moment;
  sensor_.update(at_sensor, substep_s_);
  truth_.sensor_wrench = at_sensor;
}

void SimDevice::substep() noexcept {
  const int n = chain_->dof();
  apply_due_commands();
  for (int i = 0; i < n; ++i)
    truth_.motor_torque[i] = drives_[static_cast<std::size_t>(i)].step(command_[i], substep_s_);
  chain_->prepare();
  const Eigen::Isometry3d handle = chain_->handle_pose();
  const Vector6d twist = chain_->handle_twist();
  const double t = static_cast<double>(simulated_ns_) * 1e-9;
  Vector6d wrench = attachment_.step(t, substep_s_, handle, twist);
  const WallWrench wall = wall_.wrench(handle, twist.head<3>(), twist.tail<3>());
  wrench.head<3>() += wall.force;
  wrench.tail<3>() += wall.torque;
  if (passive_gimbal_) wrench.tail<3>().setZero();
  if (sensor_present_) sensor_reading(handle, twist, wrench);
  truth_.handle_pose = handle;
  truth_.handle_twist = twist;
  truth_.handle_wrench = wrench;
  chain_->step(substep_s_, truth_.motor_torque, wrench);
  if (speed_monitor_ && truth_.overspeed_joint < 0) {
    for (int i = 0; i < n; ++i) {
      if (std::abs(chain_->link_velocity()[i]) > speed_limits_[i]) {
        truth_.overspeed_joint = i;
        break;
      }
    }
  }
}

RuntimeReply SimDevice::handle_request(std::string_view name, const std::vector<double>& values) {
  const double now = static_cast<double>(simulated_now_ns_.load(std::memory_order_relaxed)) * 1e-9;
  AttachmentSettings a = requested_;
  a.keep_anchor = false;  // every request but a move re-anchors the hand at the handle
  if (name == "operator.release") {
    a.kind = AttachmentKind::none;
  } else if (name == "operator.push") {
    if (values.size() != 3 && values.size() != 4) return {false, "operator.push takes fx fy fz [ramp_s]"};
    const double ramp = values.size() == 4 ? values[3] : 0.5;
    const Eigen::Vector3d f(values[0], values[1], values[2]);
    if (!f.allFinite() || f.norm() > 200.0 || !(ramp >= 0.0 && ramp <= 60.0))
      return {false, "operator.push: |force| up to 200 N, ramp 0..60 s"};
    // Profiles run on the attachment's own clock, which restarts when the new settings take hold.
    const Eigen::Vector3d from =
        a.kind == AttachmentKind::operator_hand ? a.force.at(now - requested_at_s_) : Eigen::Vector3d::Zero();
    a.kind = AttachmentKind::operator_hand;
    a.force.kind = Profile::Kind::ramp_to;
    a.force.from = from;
    a.force.value = f;
    a.force.start_s = 0.0;
    a.force.duration_s = ramp;
    if (a.motion.kind == Profile::Kind::ramp_to) a.motion = Profile{};  // after a move: the hand stays put
  } else if (name == "operator.move") {
    if (values.size() != 3 && values.size() != 4) return {false, "operator.move takes dx dy dz [duration_s]"};
    const double duration = values.size() == 4 ? values[3] : 1.0;
    const Eigen::Vector3d d(values[0], values[1], values[2]);
    if (!d.allFinite() || d.norm() > 1.0 || !(duration >= 0.0 && duration <= 60.0))
      return {false, "operator.move: up to 1 m, duration 0..60 s"};
    if (a.kind != AttachmentKind::operator_hand) return {false, "operator.move: no operator holds the handle"};
    // The hand's target moves by d from where it aims now, over the duration, and holds there. The anchor, the
    // hand and the profiles' clock stay: the voluntary force goes on as it was.
    const double local = now - requested_at_s_;
    const Eigen::Vector3d from = a.motion.at(local);
    a.motion = Profile{};
    a.motion.kind = Profile::Kind::ramp_to;
    a.motion.from = from;
    a.motion.value = from + d;
    a.motion.start_s = local;
    a.motion.duration_s = duration;
    a.keep_anchor = true;
    requested_ = a;
    request_attachment(a);
    return {true, "operator.move accepted"};
  } else if (name == "operator.grasp") {
    if (values.size() != 1 || !(values[0] >= 0.0 && values[0] <= 1.0))
      return {false, "operator.grasp takes one value in 0..1"};
    a.grasp = values[0];
  } else {
    return {false, "the simulated device accepts operator.push, operator.move, operator.release and operator.grasp"};
  }
  requested_ = a;
  requested_at_s_ = now;
  request_attachment(a);
  return {true, std::string(name) + " accepted"};
}

Outcome SimDevice::home() {
  if (!enabled_) return Outcome::failure("drives not enabled");
  // The index pulses are found at once: the simulation knows where they are.
  homed_ = true;
  encoder_offset_.setZero();
  return Outcome::success();
}

Outcome SimDevice::reset_fault() {
  if (!enabled_) return Outcome::failure("drives not enabled");
  if (truth_.overspeed_joint < 0) return Outcome::success();
  for (int i = 0; i < chain_->dof(); ++i)
    if (std::abs(chain_->link_velocity()[i]) > speed_limits_[i])
      return Outcome::failure("a joint is still over its speed limit: the speed monitor cannot be reset");
  truth_.overspeed_joint = -1;
  return Outcome::success();
}

Outcome SimDevice::read(const CycleTime& cycle, DeviceState& state) {
  if (!enabled_) return Outcome::failure("drives not enabled");
  if (attachment_requests_.take(pending_)) attachment_.select(pending_);
  simulated_now_ns_.store(cycle.time_ns, std::memory_order_relaxed);
  // Advance to the cycle's time; a gap of more than 10 periods (a stalled loop) is skipped, which bounds
  // the time read() takes.
  const std::int64_t max_steps = 10 * std::max<std::int64_t>(1, cycle.period_ns / substep_ns_);
  std::int64_t steps = 0;
  while (simulated_ns_ + substep_ns_ <= cycle.time_ns && steps < max_steps) {
    substep();
    simulated_ns_ += substep_ns_;
    ++steps;
  }
  if (simulated_ns_ + substep_ns_ <= cycle.time_ns) simulated_ns_ = cycle.time_ns;

  const int n = chain_->dof();
  state.timestamp_ns = cycle.time_ns;
  for (int i = 0; i < n; ++i) {
    state.joints.position[i] = quantise_encoder(chain_->motor_position()[i] - encoder_offset_[i], counts_per_rev_[i]);
    state.joints.velocity[i] = 0.0;  // not measured: controllers differentiate, as on the hardware
    state.joints.effort[i] = joint_torque_sensors_ ? std::round(chain_->spring_torque()[i] / joint_torque_resolution_) *
                                                         joint_torque_resolution_
                                                   : truth_.motor_torque[i];
  }
  if (sensor_present_) {
    const Vector6d w = sensor_.read();
    state.sensor_wrench.force = w.head<3>();
    state.sensor_wrench.torque = w.tail<3>();
    truth_.sensor_saturated = sensor_.saturated();
    state.sensor_saturated = truth_.sensor_saturated;
  }
  if (accelerations_) read_accelerations(state);
  truth_.link_position = chain_->link_position();
  truth_.link_velocity = chain_->link_velocity();
  truth_.motor_position = chain_->motor_position();
  truth_.motor_velocity = chain_->motor_velocity();
  truth_.spring_torque = chain_->spring_torque();
  truth_.friction_torque = chain_->friction_torque();
  truth_.time_s = static_cast<double>(simulated_ns_) * 1e-9;
  if (truth_.overspeed_joint >= 0)
    return Outcome::failure("a drive's speed monitor tripped: a joint went over its speed limit (latched)");
  if (!homed_) return Outcome::failure("not homed: positions are relative until homing finds the encoders' index");
  return Outcome::success();
}

void SimDevice::read_accelerations(DeviceState& state) noexcept {
  // Classical acceleration of the sensor from the links' last acceleration: J qdd + dJ/dt qd.
  FlexibleChain::FrameAcceleration f = chain_->frame_acceleration(sensor_frame_);
  Vector6d& a = f.acceleration;
  a.head<3>() -= chain_->link_model().gravity();  // an accelerometer measures acceleration minus gravity
  const Eigen::Matrix3d rt = f.pose.linear().transpose();
  truth_.sensor_acceleration.head<3>() = rt * a.head<3>();
  truth_.sensor_acceleration.tail<3>() = rt * a.tail<3>();
  const auto quantise = [](double v, double resolution, double range) {
    return std::fmax(-range, std::fmin(range, std::round(v / resolution) * resolution));
  };
  for (int i = 0; i < 3; ++i) {
    state.sensor_acceleration.linear[i] =
        quantise(truth_.sensor_acceleration[i], acceleration_resolution_[0], acceleration_range_[0]);
    state.sensor_acceleration.angular[i] =
        quantise(truth_.sensor_acceleration[3 + i], acceleration_resolution_[1], acceleration_range_[1]);
  }
}

Outcome SimDevice::write(const CycleTime& /*cycle*/, const JointCommand& command) {
  if (!enabled_) return Outcome::failure("drives not enabled");
  if (command.torque_nm.size() != command_.size()) return Outcome::failure("a command for another number of joints");
  if (command_delay_ns_ == 0) {
    command_ = command.torque_nm;
    return Outcome::success();
  }
  if (delayed_count_ == kMaxDelayed) {  // cannot happen at one write per cycle (checked in configure)
    delayed_head_ = (delayed_head_ + 1) % kMaxDelayed;
    --delayed_count_;
  }
  DelayedCommand& d = delayed_[(delayed_head_ + delayed_count_) % kMaxDelayed];
  d.due_ns = simulated_ns_ + command_delay_ns_;
  d.torque = command.torque_nm;
  ++delayed_count_;
  return Outcome::success();
}

void SimDevice::disable() {
  enabled_ = false;
  command_.setZero();
  delayed_count_ = 0;
  for (Drive& d : drives_) d.reset();
}

bool SimDevice::simulated_truth(SimulatedTruth& out) const {
  const GroundTruth& t = truth_;
  out.time_s = t.time_s;
  out.link_position = t.link_position;
  out.link_velocity = t.link_velocity;
  out.motor_position = t.motor_position;
  out.motor_velocity = t.motor_velocity;
  out.friction_torque = t.friction_torque;
  out.motor_torque = t.motor_torque;
  out.handle_pose.position = t.handle_pose.translation();
  out.handle_pose.orientation = Eigen::Quaterniond(t.handle_pose.linear());
  out.handle_twist.linear = t.handle_twist.head<3>();
  out.handle_twist.angular = t.handle_twist.tail<3>();
  out.handle_wrench.force = t.handle_wrench.head<3>();
  out.handle_wrench.torque = t.handle_wrench.tail<3>();
  return true;
}

}  // namespace hapticd::sim
