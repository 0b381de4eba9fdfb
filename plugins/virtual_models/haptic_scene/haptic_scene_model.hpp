#pragma once
// The haptic scene model ("haptic_scene"; docs/haptic-scene.md): the device's proxy (scene/proxy.hpp) in the
// shapes of a scene file, rendered at loop rate - no engine round trip is in the loop.
//   display: impedance   the device displays the proxy's force on the handle (TaskTarget::wrench)
//   display: admittance  a virtual admittance (every parameter of the `admittance` model) is the goal the proxy
//                        follows: the scene's force acts on the virtual body, which the inner motion loop tracks
// The scene: the model's own scene file (`scene`), or the session's scene (its `scene` section), which the
// session's devices share and engines edit at run time (scene/shared_scene.hpp: the loop takes each new version
// whole and plays its moving objects' poses back). Read, checked and built off the loop; the loop only queries it. The
// scene's force passes the safety layer's passivity observer and controller (the engine port, as an engine's force
// does) and the rendered-wrench limits.
#include <Eigen/Core>

#include "hapticd/scene/proxy.hpp"
#include "hapticd/scene/scene.hpp"
#include "hapticd/scene/shared_scene.hpp"
#include "hapticd/virtual_model.hpp"
#include "virtual_admittance.hpp"

namespace hapticd::models {

class HapticSceneModel final : public VirtualModel {
 public:
  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const PluginContext& context) override;
  Outcome activate(const VirtualModelInput& current) override;
  Outcome update(const CycleTime& cycle, const VirtualModelInput& input, TaskTarget& target) override;
  void deactivate() override {}
  void tune(const Parameters& parameters) override { admittance_.tune(parameters); }

  // What the proxy did in the last cycle (scene frame); for tests and the live view.
  [[nodiscard]] const scene::ProxyState& proxy() const noexcept { return proxy_.state(); }
  // The scene's frame in the world: its origin (world), the handle's position at activation with `origin: handle`.
  [[nodiscard]] const Eigen::Vector3d& scene_origin() const noexcept { return origin_; }

 private:
  scene::Scene own_scene_;                        // from the model's own scene file
  scene::SharedScene::Reader* reader_ = nullptr;  // or the session's scene
  scene::GodObject proxy_;
  VirtualAdmittance admittance_;
  bool admittance_display_ = false;
  bool origin_at_handle_ = false;
  double proxy_radius_m_ = 0.0;  // reported with the contacts (the live view draws the proxy)
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
};

}  // namespace hapticd::models
