#include "support/coupled_scene.hpp"

#include <stdexcept>

#include "support/test_paths.hpp"
#include "support/test_session.hpp"

namespace hapticd::test {

namespace {

server::Session build(const std::string& scene, const std::vector<std::string>& overrides,
                      const std::string& session_file) {
  const std::string file = session_file.empty() ? source_dir() + "/config/scenes/" + scene + ".yaml"
                                                : source_dir() + "/config/scenes/" + session_file;
  return server::Session::from_file(file, {.overrides = overrides, .plugin_paths = {plugin_dir()}});
}

double parameter(server::Session& s, const std::string& device, const std::string& name, double otherwise) {
  const RuntimeReply r = s.request(device, server::DeviceRequest{server::DeviceRequest::Kind::get_parameter, name, {}});
  return r.accepted && !r.values.empty() ? r.values.front() : otherwise;
}

}  // namespace

CoupledScene::CoupledScene(const std::string& scene, const std::vector<std::string>& overrides,
                           const std::string& session_file)
    : session_(build(scene, overrides, session_file)), devices_(session_.device_names()) {
  session_.step(1);  // the first cycle: the start poses
  std::vector<Eigen::Vector3d> starts;
  for (const std::string& d : devices_) starts.push_back(session_.device(d).task.pose.position);
  mujoco::WorldOptions options;
  options.scene = source_dir() + "/config/scenes/" + scene + ".xml";
  options.devices = devices_;
  options.state_period_s = session_.period_s();
  options.scene_to_world = mujoco::scene_frame(starts);
  world_ = std::make_unique<mujoco::CoupledWorld>(options);
  hands_.resize(devices_.size());
  for (std::size_t i = 0; i < devices_.size(); ++i) {
    mujoco::CouplingGains g;
    g.stiffness_n_per_m = parameter(session_, devices_[i], "virtual_model.coupling_stiffness_n_per_m", 0.0);
    g.damping_n_s_per_m = parameter(session_, devices_[i], "virtual_model.coupling_damping_n_s_per_m", 0.0);
    if (parameter(session_, devices_[i], "virtual_model.rotation", 0.0) != 0.0) {
      g.rotational_stiffness_n_m_per_rad =
          parameter(session_, devices_[i], "virtual_model.coupling_rotational_stiffness_n_m_per_rad", 0.0);
      g.rotational_damping_n_m_s =
          parameter(session_, devices_[i], "virtual_model.coupling_rotational_damping_n_m_s", 0.0);
    }
    if (!(g.stiffness_n_per_m > 0.0)) throw std::runtime_error(devices_[i] + ": the scene's session has no coupling");
    world_->set_gains(i, g);
    const server::DeviceView v = session_.device(devices_[i]);
    world_->place(i, mujoco::Hand{v.task.pose, v.handle_twist});
    const DeviceDescription d = session_.description(devices_[i]);
    arms_.push_back(world_->arm_bodies(i) > 0
                        ? std::make_unique<mujoco::ArmModel>(d.robot_model_file, 0.02, d.base_pose)
                        : nullptr);
  }
}

void CoupledScene::step(std::uint64_t cycles) {
  for (std::uint64_t k = 0; k < cycles; ++k) {
    for (std::size_t i = 0; i < devices_.size(); ++i) {
      const server::DeviceView v = session_.device(devices_[i]);
      hands_[i] = mujoco::Hand{v.task.pose, v.handle_twist};
      if (arms_[i]) {
        world_->set_arm(
            i, arms_[i]->place(std::span<const double>(v.state.joints.position.data(),
                                                       static_cast<std::size_t>(v.state.joints.position.size()))));
      }
    }
    if (!world_->step(hands_).stable) ++unstable_;
    ++sequence_;
    for (std::size_t i = 0; i < devices_.size(); ++i) {
      const mujoco::Proxy p = world_->proxy(i);
      EngineInput e;
      e.has_proxy = true;
      e.proxy_pose = p.pose;
      e.proxy_twist = p.twist;
      e.sequence = sequence_;
      session_.set_engine_input(devices_[i], e);
    }
    session_.step(1);
    for (std::size_t i = 0; i < devices_.size(); ++i) lowest_energy_ = std::min(lowest_energy_, port_energy_j(i));
  }
}

void CoupledScene::drive(const std::string& device, const std::string& command, const std::vector<double>& values) {
  const RuntimeReply r =
      session_.request(device, server::DeviceRequest{server::DeviceRequest::Kind::drive_operator, command, values});
  if (!r.accepted) throw std::runtime_error(device + ": operator " + command + ": " + r.message);
}

void CoupledScene::passivity_control(const std::string& device, bool on) {
  const RuntimeReply r = session_.request(
      device,
      server::DeviceRequest{server::DeviceRequest::Kind::set_parameter, "safety.passivity_control", {on ? 1.0 : 0.0}});
  if (!r.accepted) throw std::runtime_error(device + ": safety.passivity_control: " + r.message);
}

server::DeviceView CoupledScene::view(std::size_t device) const { return session_.device(devices_.at(device)); }

Eigen::Vector3d CoupledScene::in_scene(const std::string& body) const {
  const auto pose = world_->body_pose(body);
  if (!pose) throw std::runtime_error("the scene has no body " + body);
  return to_scene(pose->position);
}

Eigen::Vector3d CoupledScene::to_scene(const Eigen::Vector3d& world) const {
  return world_->scene_to_world().inverse() * world;
}

double CoupledScene::port_energy_j(std::size_t device) {
  return session_.impl().devices.at(device)->safety().guard().port_energy_j();
}

}  // namespace hapticd::test
