// Example virtual model of admittance type: a point mass with damping, moved by the operator's force. It answers
// the desired motion of the handle, which the chain's inverse kinematics and controller make the device follow;
// the safety layer's force (walls, speed damping) acts on the mass too, so the mass does not fight the walls.
#pragma once
#include <Eigen/Core>
#include <hapticd/plugin.hpp>

namespace example {

class PointMassModel final : public hapticd::VirtualModel {
 public:
  static hapticd::ParameterSchema parameter_schema();

  void configure(const hapticd::Parameters& p, const hapticd::PluginContext& context) override;
  hapticd::Outcome activate(const hapticd::VirtualModelInput& current) override;
  hapticd::Outcome update(const hapticd::CycleTime& cycle, const hapticd::VirtualModelInput& in,
                          hapticd::TaskTarget& target) override;
  void deactivate() override {}

 private:
  double mass_kg_ = 1.0, damping_ = 0.0;
  Eigen::Vector3d position_ = Eigen::Vector3d::Zero(), velocity_ = Eigen::Vector3d::Zero();
};

}  // namespace example
