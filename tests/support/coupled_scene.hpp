#pragma once
// A session of config/scenes/ coupled to its MuJoCo scene in lockstep: each cycle the session steps, the world
// takes the hands its devices' views give (the virtual body's pose and the handle's twist, as a state over DDS
// gives them to hapticd-mujoco-engine) and steps one state period, and each proxy goes back as the device's engine
// input for the next cycle - the engine's round trip of one cycle, without DDS, repeatable. Errors throw
// std::runtime_error (a refused operator request, a body the scene lacks); used by tests and benchmarks.
#include <memory>
#include <string>
#include <vector>

#include "assembly/session_impl.hpp"
#include "hapticd/mujoco/coupled_world.hpp"
#include "hapticd/server/session.hpp"
#include "session/device_session.hpp"

namespace hapticd::test {

class CoupledScene {
 public:
  // scene: a name of config/scenes/ (<scene>.xml with <scene>.yaml, or session_file: another session there). Where the
  // scene shows a device's arm (arm_* bodies), its robot model's capsules move them, as --arm does in the engine.
  explicit CoupledScene(const std::string& scene, const std::vector<std::string>& overrides = {},
                        const std::string& session_file = "");

  void step(std::uint64_t cycles = 1);
  // The simulated operator of a device: "push" {fx, fy, fz, ramp_s}, "move" {dx, dy, dz, duration_s}, ...
  void drive(const std::string& device, const std::string& command, const std::vector<double>& values);
  // Turns the device's passivity controller on or off.
  void passivity_control(const std::string& device, bool on);

  [[nodiscard]] server::Session& session() { return session_; }
  [[nodiscard]] mujoco::CoupledWorld& world() { return *world_; }
  [[nodiscard]] server::DeviceView view(std::size_t device = 0) const;
  [[nodiscard]] mujoco::Proxy proxy(std::size_t device = 0) const { return world_->proxy(device); }
  // A body's position in the scene's frame.
  [[nodiscard]] Eigen::Vector3d in_scene(const std::string& body) const;
  [[nodiscard]] Eigen::Vector3d to_scene(const Eigen::Vector3d& world) const;
  // The energy the server's passivity observer has measured at the device's engine port since activation, and the
  // lowest it has been.
  [[nodiscard]] double port_energy_j(std::size_t device = 0);
  [[nodiscard]] double lowest_port_energy_j() const { return lowest_energy_; }
  [[nodiscard]] std::uint64_t unstable_steps() const { return unstable_; }

 private:
  server::Session session_;
  std::unique_ptr<mujoco::CoupledWorld> world_;
  std::vector<std::string> devices_;
  std::vector<mujoco::Hand> hands_;
  std::vector<std::unique_ptr<mujoco::ArmModel>> arms_;  // per device; null where the scene shows no arm
  std::uint64_t sequence_ = 0;
  double lowest_energy_ = 0.0;
  std::uint64_t unstable_ = 0;
};

}  // namespace hapticd::test
