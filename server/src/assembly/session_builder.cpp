#include "assembly/session_builder.hpp"

#include <algorithm>

#include "config/config_error.hpp"
#include "config/yaml_reader.hpp"
#include "hapticd/model/urdf_loader.hpp"

namespace hapticd::server {
namespace {

// A plugin threw from configure() (other than a ParameterError, which is a mistake in the session file): the
// device is isolated in its safe state and the others run (docs/safety.md).
struct PluginConfigureError {
  ConfigError error;
};

int line_from_origin(const std::string& origin, int fallback) {
  const auto colon = origin.rfind(':');
  if (colon == std::string::npos) return fallback;
  try {
    return std::stoi(origin.substr(colon + 1));
  } catch (const std::exception&) {
    return fallback;
  }
}

// A chain plugin for the other kind of device (a joint controller on a handle, a handle's on joints): the key
// of the plugin and why.
void check_interface(PluginKind kind, const PluginConfig& pc, const std::string& file, const PluginHandle& handle,
                     const PluginContext& context) {
  if (kind == PluginKind::device || context.device == nullptr ||
      supports(handle.descriptor->device_interfaces, context.device->interface))
    return;
  const bool on_handle = context.device->interface == DeviceInterface::handle;
  throw ConfigError(file, pc.line, pc.key_path + ".plugin",
                    "device '" + context.device_name + "' is a " + (on_handle ? "handle" : "joint") + " device (" +
                        context.device->model + "); " + std::string(to_string(kind)) + " '" + pc.plugin + "' drives " +
                        (on_handle ? "joints" : "handle devices") + " only" +
                        (on_handle ? ": a handle device takes its force directly (controller: handle_force)" : ""));
}

template <class T, class Context>
PluginInstance<T> load_and_configure(PluginKind kind, const PluginConfig& pc, const SessionConfig& config,
                                     PluginLoader& loader, const Context& context) {
  const std::string file = config.file.string();
  PluginHandle handle;
  try {
    handle = loader.find(kind, pc.plugin, pc.library);
  } catch (const PluginLoadError& e) {
    throw ConfigError(file, pc.line, pc.key_path + ".plugin", e.what());
  }
  if constexpr (requires { context.device; }) check_interface(kind, pc, file, handle, context);
  const ParameterSchema schema = handle.descriptor->parameter_schema();
  const std::string parameters_path = pc.key_path + ".parameters";
  const Parameters parameters = read_parameters(pc.parameters, schema, file, parameters_path, pc.line);

  PluginInstance<T> instance;
  try {
    instance = create_plugin<T>(handle);
  } catch (const PluginLoadError& e) {
    throw ConfigError(file, pc.line, pc.key_path + ".plugin", e.what());
  }
  try {
    instance->configure(parameters, context);
  } catch (const ParameterError& e) {
    throw ConfigError(file, line_from_origin(parameters.origin(e.key()), pc.line), parameters_path + "." + e.key(),
                      e.what());
  } catch (const DeviceUnavailable& e) {
    throw PluginConfigureError{ConfigError(file, pc.line, pc.key_path, "device unavailable: " + std::string(e.what()))
                                   .set_device_unavailable()};
  } catch (const std::exception& e) {
    throw PluginConfigureError{ConfigError(file, pc.line, pc.key_path,
                                           "plugin '" + pc.plugin + "' failed to configure: " + std::string(e.what()))};
  } catch (...) {
    throw PluginConfigureError{
        ConfigError(file, pc.line, pc.key_path, "plugin '" + pc.plugin + "' failed to configure")};
  }
  instance.parameters = parameters;
  return instance;
}

// The model with the collision geometry the session file gives (in its link frames), else the URDF's, else
// capsules along the skeleton. Before the model is mounted: the capsules are in the URDF root's frame.
model::RobotModel with_collision_of(const DeviceConfig& dc, const model::RobotModel& robot, const std::string& file) {
  if (dc.collision.capsules.empty()) {
    if (!robot.collision().empty() || dc.collision.skeleton_radius_m <= 0.0) return robot;
    return robot.with_collision(model::skeleton_capsules(robot, dc.collision.skeleton_radius_m));
  }
  std::vector<model::Capsule> capsules;
  for (const CapsuleConfig& c : dc.collision.capsules) {
    const int frame = robot.frame_id(c.link);
    if (frame < 0)
      throw ConfigError(file, c.line, c.key_path + ".link",
                        "device '" + dc.name + "': no link '" + c.link + "' in its robot model");
    const model::Frame& f = robot.frame(frame);
    capsules.push_back(model::Capsule{c.link, f.body, f.placement * c.from, f.placement * c.to, c.radius_m});
  }
  try {
    return robot.with_collision(std::move(capsules));
  } catch (const std::invalid_argument& e) {
    throw ConfigError(file, dc.collision.capsules.front().line, dc.collision.capsules.front().key_path, e.what());
  }
}

// The device's robot model, parsed once for the estimator and the whole chain, mounted at the device's base pose
// (its poses, Jacobians and gravity in the world frame); checked against the device.
std::shared_ptr<const model::RobotModel> robot_model_of(const DeviceConfig& dc, const DeviceDescription& description,
                                                        const std::string& file) {
  if (description.robot_model_file.empty()) return nullptr;
  std::shared_ptr<const model::RobotModel> robot;
  try {
    const model::RobotModel own = model::load_robot_model(description.robot_model_file);
    robot = std::make_shared<const model::RobotModel>(
        with_collision_of(dc, own, file).with_base(to_isometry(description.base_pose)));
  } catch (const ConfigError&) {
    throw;
  } catch (const std::exception& e) {
    throw ConfigError(file, dc.device.line, dc.device.key_path,
                      "device '" + dc.name + "': its robot model: " + e.what());
  }
  if (robot->dof() != description.dof())
    throw ConfigError(file, dc.device.line, dc.device.key_path,
                      "device '" + dc.name + "': its robot model " + description.robot_model_file + " has " +
                          std::to_string(robot->dof()) + " joints, the device " + std::to_string(description.dof()));
  return robot;
}

// A handle device (hapticd/handle.hpp): no robot model; its joints are the handle's axes, with velocities it
// reports.
void prepare_handle_device(const DeviceConfig& dc, DeviceChain& chain, const std::string& file) {
  DeviceDescription& d = chain.description;
  if (!d.robot_model_file.empty())
    throw ConfigError(file, dc.device.line, dc.device.key_path,
                      "device '" + dc.name + "' is a handle device and names a robot model; a handle device has none");
  if (!(d.handle.max_force_n > 0.0) || (d.handle.actuated_torque && !(d.handle.max_torque_nm > 0.0)) ||
      (d.handle.actuated_gripper && !(d.handle.max_gripper_force_n > 0.0)))
    throw ConfigError(file, dc.device.line, dc.device.key_path,
                      "device '" + dc.name + "' is a handle device without force limits for its actuated axes");
  d.joints = handle_axes(d.handle);
  d.reports_joint_velocity = true;
}

// A handle device's safety box is the device's own workspace unless the session gives one.
void default_handle_workspace(DeviceChain& chain) {
  const DeviceDescription& d = chain.description;
  if (d.interface != DeviceInterface::handle) return;
  SafetySettings& safety = chain.safety;
  bool box = true;
  for (std::size_t i = 0; i < 3; ++i) box = box && safety.workspace_min_m[i] < safety.workspace_max_m[i];
  if (!box) {
    // The device's box, in the world: the box around its corners turned by the base pose.
    const Eigen::Isometry3d base = to_isometry(d.base_pose);
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = Eigen::Vector3d::Constant(-1e9);
    for (int c = 0; c < 8; ++c) {
      Eigen::Vector3d corner;
      for (int i = 0; i < 3; ++i) corner[i] = (c >> i) & 1 ? d.handle.workspace_max[i] : d.handle.workspace_min[i];
      const Eigen::Vector3d w = base * corner;
      lo = lo.cwiseMin(w);
      hi = hi.cwiseMax(w);
    }
    for (std::size_t i = 0; i < 3; ++i) {
      safety.workspace_min_m[i] = lo[static_cast<int>(i)];
      safety.workspace_max_m[i] = hi[static_cast<int>(i)];
    }
  }
}

}  // namespace

std::uint64_t device_seed(std::uint64_t session_seed, std::size_t device_index) noexcept {
  std::uint64_t z = session_seed + 0x9e3779b97f4a7c15ULL * (device_index + 1);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

namespace {

// The session's scene (its `scene` section; null without): its plugin loaded - only then, so a session without a
// scene never maps the scene's libraries - and configured (its scene file read, checked and built) before any
// device's chain. Any failure fails the start: the scene belongs to every device.
SessionScene session_scene(const SessionConfig& config, PluginLoader& loader) {
  if (!config.scene) return nullptr;
  PluginContext context;
  context.rate_hz = config.server.rate_hz;
  context.seed = config.server.seed;
  context.config_directory = config.file.parent_path();
  try {
    return std::make_shared<PluginInstance<SceneService>>(
        load_and_configure<SceneService>(PluginKind::scene, *config.scene, config, loader, context));
  } catch (const PluginConfigureError& e) {
    throw e.error;
  }
}

std::vector<std::unique_ptr<DeviceSession>> build_all(const SessionConfig& config, PluginLoader& loader,
                                                      std::vector<ConfigureFailure>* report) {
  std::vector<std::unique_ptr<DeviceSession>> sessions;
  const SessionScene scene = session_scene(config, loader);
  for (std::size_t i = 0; i < config.devices.size(); ++i) {
    const DeviceConfig& dc = config.devices[i];
    PluginContext context;
    context.scene = scene ? scene->object.get() : nullptr;
    context.device_name = dc.name;
    context.rate_hz = config.server.rate_hz;
    context.seed = device_seed(config.server.seed, i);
    context.config_directory = config.file.parent_path();
    context.base_pose = dc.base_pose;

    DeviceChain chain;
    chain.scene = scene;
    try {
      chain.device = load_and_configure<Device>(PluginKind::device, dc.device, config, loader, context);
    } catch (const PluginConfigureError& e) {
      // Without a configured device plugin there is nothing to drive: its drives stay unpowered.
      if (report == nullptr) throw e.error;
      report->push_back({dc.name, e.error, false});
      continue;
    }
    chain.description = chain.device->description();
    chain.description.base_pose = dc.base_pose;
    if (chain.description.interface == DeviceInterface::handle) prepare_handle_device(dc, chain, config.file.string());
    context.device = &chain.description;
    chain.robot_model = robot_model_of(dc, chain.description, config.file.string());
    context.robot_model = chain.robot_model.get();
    const auto build_scheme = [&](const std::string& name, const std::optional<PluginConfig>& virtual_model,
                                  const std::optional<PluginConfig>& inverse_kinematics,
                                  const PluginConfig& controller) {
      if (inverse_kinematics && chain.description.interface == DeviceInterface::handle)
        throw ConfigError(config.file.string(), inverse_kinematics->line, inverse_kinematics->key_path,
                          "device '" + dc.name + "' is a handle device (" + chain.description.model +
                              "): its kinematics are the vendor's; inverse kinematics needs joints");
      SchemeChain scheme;
      scheme.name = name;
      if (virtual_model)
        scheme.virtual_model =
            load_and_configure<VirtualModel>(PluginKind::virtual_model, *virtual_model, config, loader, context);
      if (inverse_kinematics)
        scheme.inverse_kinematics = load_and_configure<InverseKinematics>(PluginKind::inverse_kinematics,
                                                                          *inverse_kinematics, config, loader, context);
      scheme.controller = load_and_configure<Controller>(PluginKind::controller, controller, config, loader, context);
      chain.schemes.push_back(std::move(scheme));
    };
    try {
      build_scheme(dc.scheme, dc.virtual_model, dc.inverse_kinematics, dc.controller);
      for (const SchemeConfig& alt : dc.alternatives)
        build_scheme(alt.name, alt.virtual_model, alt.inverse_kinematics, alt.controller);
    } catch (const PluginConfigureError& e) {
      // The device is powered but held in its safe state; its other plugins are dropped.
      if (report == nullptr) throw e.error;
      chain.schemes.clear();
      chain.configure_error = e.error.what();
      report->push_back({dc.name, e.error, true});
    }
    chain.switch_ramp_s = dc.switch_ramp_s;
    chain.engine_deadline_s = dc.engine_deadline_s;
    chain.engine_fade_s = dc.engine_fade_s;
    chain.engine_ramp_in_s = dc.engine_ramp_in_s;
    chain.safety = dc.safety;
    default_handle_workspace(chain);
    chain.period_s = 1.0 / config.server.rate_hz;

    try {
      sessions.push_back(std::make_unique<DeviceSession>(dc.name, std::move(chain)));
    } catch (const std::invalid_argument& e) {
      throw ConfigError(config.file.string(), dc.device.line, dc.device.key_path, e.what());
    }
  }
  if (report == nullptr) return sessions;
  if (sessions.empty() || std::none_of(sessions.begin(), sessions.end(),
                                       [](const auto& d) { return d->status().fault() == DeviceFault::none; })) {
    if (!report->empty()) throw report->front().error;  // nothing could run: fail the start
  }
  return sessions;
}

}  // namespace

ClockDevice clock_device(const SessionConfig& config, const std::vector<DeviceSession*>& devices) {
  const ServerSettings& server = config.server;
  if (server.clock != ClockMode::device) return {};
  const std::string file = config.file.string();
  const auto can_clock = [](const DeviceSession* d) { return d->chain().device->clock() != nullptr; };
  const auto config_of = [&](const DeviceSession* d) -> const DeviceConfig& {
    for (const DeviceConfig& dc : config.devices)
      if (dc.name == d->name()) return dc;
    return config.devices.front();  // every built device has its entry
  };
  DeviceSession* found = nullptr;
  if (!server.clock_device.empty()) {
    for (DeviceSession* d : devices)
      if (d->name() == server.clock_device) found = d;
    if (found == nullptr)
      throw ConfigError(file, server.clock_line, "server.clock_device",
                        "no device '" + server.clock_device + "' runs in this session");
    if (!can_clock(found))
      throw ConfigError(file, server.clock_line, "server.clock_device",
                        "device '" + server.clock_device + "' (plugin '" + config_of(found).device.plugin +
                            "') has no clock of its own: only a device whose SDK or service owns the servo loop can "
                            "clock the session (clock: realtime runs it on the server's clock)");
  } else {
    for (DeviceSession* d : devices) {
      if (!can_clock(d)) continue;
      if (found != nullptr)
        throw ConfigError(file, server.clock_line, "server.clock",
                          "devices '" + found->name() + "' and '" + d->name() +
                              "' can both clock the session: name one in server.clock_device");
      found = d;
    }
    if (found == nullptr)
      throw ConfigError(file, server.clock_line, "server.clock",
                        "clock: device, but no device of the session has a clock of its own (only a device whose SDK "
                        "or service owns the servo loop has; clock: realtime runs the session on the server's clock)");
  }
  if (config_of(found).safety.max_stall_s <= 0.0)
    throw ConfigError(file, server.clock_line, "server.clock",
                      "device '" + found->name() +
                          "' clocks the session, so its stall watchdog must be on (safety.max_stall_s above 0): a "
                          "device that stops ticking stops the loop");
  return {found, config_of(found).safety.max_stall_s};
}

std::vector<std::unique_ptr<DeviceSession>> build_sessions(const SessionConfig& config, PluginLoader& loader,
                                                           std::vector<ConfigureFailure>* report) {
  try {
    std::vector<std::unique_ptr<DeviceSession>> sessions = build_all(config, loader, report);
    std::vector<DeviceSession*> built;
    for (const auto& d : sessions) built.push_back(d.get());
    (void)clock_device(config, built);  // checked before anything is powered
    return sessions;
  } catch (const ConfigError& e) {
    throw_if_overridden(e, config.overrides);  // a plugin parameter an override set: the error names it
    throw;
  }
}

std::vector<std::unique_ptr<GroupStage>> build_group_stages(const SessionConfig& config,
                                                            const std::vector<std::unique_ptr<DeviceSession>>& devices,
                                                            PluginLoader& loader) {
  std::vector<std::unique_ptr<GroupStage>> stages;
  for (const GroupConfig& g : config.groups) {
    std::vector<DeviceSession*> members;
    for (const std::string& name : g.devices)
      for (const auto& d : devices)
        if (d->name() == name) members.push_back(d.get());
    if (g.min_distance_m > 0.0 || g.repulsion.distance_m > 0.0)
      for (const DeviceSession* d : members)
        if (d->chain().robot_model == nullptr)
          throw ConfigError(config.file.string(), g.line,
                            g.key_path + (g.min_distance_m > 0.0 ? ".min_distance_m" : ".repulsion"),
                            "group '" + g.name + "' checks distances, but device '" + d->name() +
                                "' has no robot model (no collision geometry)");
    GroupModelContext context;
    context.group_name = g.name;
    for (const DeviceSession* d : members) context.devices.push_back(d->name());
    context.rate_hz = config.server.rate_hz;
    context.config_directory = config.file.parent_path();
    auto stage = std::make_unique<GroupStage>(g.name, std::move(members), g.min_distance_m, g.repulsion,
                                              1.0 / config.server.rate_hz, g.own_loop);
    if (g.model) {
      try {
        stage->set_model(load_and_configure<GroupModel>(PluginKind::group_model, *g.model, config, loader, context));
      } catch (const PluginConfigureError& e) {
        throw e.error;  // a group's model that cannot configure is the session's error (it holds several devices)
      }
    }
    stages.push_back(std::move(stage));
  }
  return stages;
}

}  // namespace hapticd::server
