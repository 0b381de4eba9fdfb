#pragma once
#include "hapticd/inverse_kinematics.hpp"

namespace hapticd::test_plugins {

// Identity map from the task target's x, y, z to the first (up to) three joints: the IK of a Cartesian
// device whose joints are its axes.
class AxisInverseKinematics final : public InverseKinematics {
 public:
  static ParameterSchema parameter_schema() { return {}; }

  void configure(const Parameters& parameters, const PluginContext& context) override;
  Outcome activate(const InverseKinematicsInput& current) override;
  Outcome update(const CycleTime& cycle, const InverseKinematicsInput& input, JointTarget& target) override;
  void deactivate() override {}

 private:
  int axes_ = 0;
};

}  // namespace hapticd::test_plugins
