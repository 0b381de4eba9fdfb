#include "config/teleoperation_settings.hpp"

#include "config/config_error.hpp"
#include "config/yaml_reader.hpp"

namespace hapticd::server {

ParameterSchema teleoperation_settings_schema() {
  const teleop::LinkSettings d;
  ParameterSchema s;
  s.boolean("enabled", "run the link").default_value(true);
  s.string("device", "this server's device on the link; empty: the session's only device").default_value(std::string());
  s.string("peer", "the other server's device (its name in its session)");
  s.string("role", "master: the device the operator holds; remote: the manipulator in its environment")
      .choices({"master", "remote"});
  s.string("architecture",
           "position_force: the master sends its motion, the remote returns its environment's force; "
           "position_position: a spring-damper across the link")
      .choices({"position_force", "position_position"})
      .default_value(std::string(teleop::to_string(d.architecture)));
  s.string("passivity",
           "tdpa: the time-domain passivity approach (energy observers and controllers at both ports); wave: wave "
           "variables (position_force only); none: the delayed link as it is")
      .choices({"tdpa", "wave", "none"})
      .default_value(std::string(teleop::to_string(d.passivity)));
  s.real("motion_scale", "the remote's motion per master motion")
      .minimum(0.01)
      .maximum(100.0)
      .default_value(d.motion_scale);
  s.real("force_scale", "the master's force per remote force")
      .minimum(0.01)
      .maximum(100.0)
      .default_value(d.force_scale);
  s.real("stiffness_n_per_m", "position_force: the remote's position controller; position_position: the coupling")
      .unit("N/m")
      .minimum(0.0)
      .maximum(1e5)
      .default_value(d.stiffness);
  s.real("damping_n_s_per_m", "its damping").unit("N s/m").minimum(0.0).maximum(1e4).default_value(d.damping);
  s.real("wave_impedance_n_s_per_m", "wave variables: the characteristic impedance b")
      .unit("N s/m")
      .minimum(0.1)
      .maximum(1e4)
      .default_value(d.wave_impedance);
  s.real("drift_time_s", "position_force: the remote's setpoint closes its drift from the master's motion over this")
      .unit("s")
      .minimum(1e-4)
      .maximum(10.0)
      .default_value(d.drift_time_s);
  s.real("max_speed_m_s", "the remote setpoint's speed limit")
      .unit("m/s")
      .minimum(1e-3)
      .maximum(10.0)
      .default_value(d.max_speed);
  s.real("max_force_n", "the force the link commands on either side at most")
      .unit("N")
      .minimum(0.0)
      .maximum(1000.0)
      .default_value(d.max_force);
  s.real("link_timeout_s",
         "no packet from the peer this long: the link is lost - the remote stops (emergency stop), the master's "
         "force fades out")
      .unit("s")
      .minimum(1e-3)
      .maximum(60.0)
      .default_value(d.link_timeout_s);
  s.real("fade_s", "the master's force fades out (and back in) over this")
      .unit("s")
      .minimum(0.0)
      .maximum(10.0)
      .default_value(d.fade_s);
  s.boolean("rotation",
            "six degrees of freedom: the handle's orientation and angular velocity go over the link too and torques "
            "come back (passivity tdpa or none; the device must render torques)")
      .default_value(d.rotation);
  s.real("rotational_stiffness_n_m_per_rad",
         "position_force: the remote's orientation controller; position_position: the coupling's rotational spring")
      .unit("N m/rad")
      .minimum(0.0)
      .maximum(1e4)
      .default_value(d.rotational_stiffness);
  s.real("rotational_damping_n_m_s_per_rad", "its damping")
      .unit("N m s/rad")
      .minimum(0.0)
      .maximum(1e3)
      .default_value(d.rotational_damping);
  s.real("max_angular_speed_rad_s", "the remote's orientation setpoint's speed limit")
      .unit("rad/s")
      .minimum(1e-3)
      .maximum(100.0)
      .default_value(d.max_angular_speed);
  s.real("max_torque_n_m", "the torque the link commands on either side at most")
      .unit("N m")
      .minimum(0.0)
      .maximum(1000.0)
      .default_value(d.max_torque);
  return s;
}

TeleoperationSettings read_teleoperation(const YAML::Node& node, const std::string& file) {
  TeleoperationSettings t;
  if (!node.IsDefined()) return t;
  t.line = line_of(node);
  if (!node.IsMap())
    throw ConfigError(file, line_of(node), "teleoperation", "expected a mapping of teleoperation settings");
  const Parameters p = read_parameters(node, teleoperation_settings_schema(), file, "teleoperation", line_of(node));
  t.enabled = p.boolean("enabled");
  t.device = p.string("device");
  t.peer = p.string("peer");
  t.role = p.string("role") == "remote" ? teleop::Role::remote : teleop::Role::master;
  teleop::LinkSettings& l = t.link;
  l.architecture = p.string("architecture") == "position_position" ? teleop::Architecture::position_position
                                                                   : teleop::Architecture::position_force;
  const std::string passivity = p.string("passivity");
  l.passivity = passivity == "none"   ? teleop::Passivity::none
                : passivity == "wave" ? teleop::Passivity::wave
                                      : teleop::Passivity::tdpa;
  l.motion_scale = p.real("motion_scale");
  l.force_scale = p.real("force_scale");
  l.stiffness = p.real("stiffness_n_per_m");
  l.damping = p.real("damping_n_s_per_m");
  l.wave_impedance = p.real("wave_impedance_n_s_per_m");
  l.drift_time_s = p.real("drift_time_s");
  l.max_speed = p.real("max_speed_m_s");
  l.max_force = p.real("max_force_n");
  l.link_timeout_s = p.real("link_timeout_s");
  l.fade_s = p.real("fade_s");
  l.rotation = p.boolean("rotation");
  l.rotational_stiffness = p.real("rotational_stiffness_n_m_per_rad");
  l.rotational_damping = p.real("rotational_damping_n_m_s_per_rad");
  l.max_angular_speed = p.real("max_angular_speed_rad_s");
  l.max_torque = p.real("max_torque_n_m");
  if (const std::string problem = teleop::link_settings_problem(l); !problem.empty())
    throw ConfigError(file, line_of(node["passivity"]) > 0 ? line_of(node["passivity"]) : line_of(node),
                      "teleoperation.passivity", problem);
  return t;
}

}  // namespace hapticd::server
