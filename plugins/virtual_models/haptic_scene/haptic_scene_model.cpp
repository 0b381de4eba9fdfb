#include "haptic_scene_model.hpp"

#include <string>

#include "hapticd/chain_state.hpp"
#include "hapticd/render_port.hpp"
#include "hapticd/scene/scene_file.hpp"
#include "hapticd/scene/shared_scene.hpp"
#include "hapticd/scene_service.hpp"

namespace hapticd::models {

ParameterSchema HapticSceneModel::parameter_schema() {
  ParameterSchema s = VirtualAdmittance::parameter_schema();  // the virtual body of admittance display
  s.string("scene",
           "the scene file (YAML: materials and objects; docs/haptic-scene.md), relative to the session file; empty: "
           "the session's scene (its `scene` section), shared with its other devices and edited at run time")
      .default_value(std::string());
  s.string("display", "impedance: the device displays the proxy's force; admittance: a virtual body follows it")
      .choices({"impedance", "admittance"})
      .default_value(std::string("impedance"));
  s.string("origin",
           "world: the scene's coordinates are the world's; handle: its origin is where the handle is "
           "when the model starts")
      .choices({"world", "handle"})
      .default_value(std::string("world"));
  s.real("proxy_radius_m", "the proxy's radius: the size of the fingertip that touches the scene")
      .unit("m")
      .minimum(0.0005)
      .maximum(0.05)
      .default_value(0.005);
  s.real("max_stiffness_n_per_m", "every material's stiffness is held to this (the device's stable limit)")
      .unit("N/m")
      .greater_than(0.0)
      .default_value(10000.0);
  s.integer("max_iterations", "the proxy's sweeps per cycle (each stops at one more contact)")
      .minimum(1)
      .maximum(16)
      .default_value(8);
  return s;
}

void HapticSceneModel::configure(const Parameters& p, const PluginContext& context) {
  std::filesystem::path file = p.string("scene");
  reader_ = nullptr;
  if (file.empty()) {
    if (context.scene == nullptr)
      throw ParameterError("scene",
                           "no scene file given and the session has no scene section: name a file here or add a "
                           "`scene` section to the session");
    reader_ =
        &context.scene->shared().add_reader(context.device_name);  // the session's scene, shared with its other devices
    reader_->refresh(0);
  } else {
    if (file.is_relative()) file = context.config_directory / file;
    try {
      own_scene_ = scene::load_scene_file(file);
    } catch (const scene::SceneFileError& e) {
      throw ParameterError("scene", e.what());
    }
  }
  scene::ProxySettings settings;
  settings.radius_m = p.real("proxy_radius_m");
  proxy_radius_m_ = settings.radius_m;
  settings.max_stiffness_n_per_m = p.real("max_stiffness_n_per_m");
  settings.max_iterations = static_cast<int>(p.integer("max_iterations"));
  proxy_.configure(settings, reader_ != nullptr ? reader_->scene() : own_scene_);
  admittance_display_ = p.string("display") == "admittance";
  origin_at_handle_ = p.string("origin") == "handle";
  if (admittance_display_) {
    admittance_.configure(p, context);
  } else {
    admittance_.configure_environment(p, context);
  }
}

Outcome HapticSceneModel::activate(const VirtualModelInput& current) {
  origin_ = origin_at_handle_ ? current.chain.handle_pose.position : Eigen::Vector3d::Zero();
  const Outcome o = admittance_.activate(current);
  proxy_.reset(current.chain.handle_pose.position - origin_);
  return o;
}

Outcome HapticSceneModel::update(const CycleTime& cycle, const VirtualModelInput& input, TaskTarget& target) {
  // The session's scene: its newest version (an engine's edit) and its moving objects' poses at this cycle.
  if (reader_ != nullptr && reader_->refresh(cycle.time_ns)) proxy_.rebind(reader_->scene());
  const ChainState& c = input.chain;
  if (admittance_display_) {
    // The virtual body is the proxy's goal: the scene's force acts on it, the motion loop makes the handle follow.
    const scene::ProxyState& s = proxy_.update(admittance_.body_position() - origin_, admittance_.body_velocity());
    if (reader_ != nullptr) reader_->report_contacts(s, proxy_radius_m_);
    RenderPort::Vector6 wrench = RenderPort::Vector6::Zero();
    wrench.head<3>() = s.force;
    RenderPort::Vector6 port_twist;
    port_twist << admittance_.body_velocity(), Eigen::Vector3d::Zero();
    return admittance_.update(cycle, input, target, input.render.engine_port(wrench, port_twist));
  }
  admittance_.take_tuning();
  const scene::ProxyState& s = proxy_.update(c.handle_pose.position - origin_, c.handle_twist.linear);
  if (reader_ != nullptr) reader_->report_contacts(s, proxy_radius_m_);
  RenderPort::Vector6 wrench = RenderPort::Vector6::Zero();
  wrench.head<3>() = s.force;
  RenderPort::Vector6 port_twist;
  port_twist << c.handle_twist.linear, c.handle_twist.angular;
  const RenderPort::Vector6 rendered = input.render.limit(input.render.engine_port(wrench, port_twist));
  display_on_handle(target, c, rendered);
  return Outcome::success();
}

}  // namespace hapticd::models
