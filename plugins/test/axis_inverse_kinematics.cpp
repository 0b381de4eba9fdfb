#include "axis_inverse_kinematics.hpp"

#include <algorithm>

namespace hapticd::test_plugins {

void AxisInverseKinematics::configure(const Parameters&, const PluginContext& context) {
  axes_ = context.device != nullptr ? std::min(3, context.device->dof()) : 0;
}

Outcome AxisInverseKinematics::activate(const InverseKinematicsInput&) { return Outcome::success(); }

Outcome AxisInverseKinematics::update(const CycleTime&, const InverseKinematicsInput& in, JointTarget& target) {
  if (!in.task.has_motion) {
    target.valid = false;
    return Outcome::success();
  }
  for (int i = 0; i < axes_; ++i) {
    target.position[i] = in.task.pose.position[i];
    target.velocity[i] = in.task.twist.linear[i];
    target.acceleration[i] = in.task.acceleration.linear[i];
  }
  target.valid = true;
  return Outcome::success();
}

}  // namespace hapticd::test_plugins
