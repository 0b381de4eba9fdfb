#pragma once
// What an inverse-kinematics plugin that resolves redundancy (n > m) offers the controller of the same chain:
// the resolution at the measured state, so task-space inner loops (resolved acceleration, inverse and
// transposed Jacobian) use the configured inverse and side criteria rather than a bare minimum-norm solution.
// The controller gets it in ControllerInput::redundancy (nullptr when the chain's IK offers none).
#include "hapticd/chain_signals.hpp"
#include "hapticd/chain_state.hpp"
#include "hapticd/export.hpp"
#include "hapticd/joint_vector.hpp"
#include "hapticd/model/model_data.hpp"

namespace hapticd {

class HAPTICD_API RedundancyResolution {
 public:
  virtual ~RedundancyResolution();

  // Acceleration level at the measured state, over the first xdd_minus_bias.size() task rows:
  //   qdd = J^W# (xdd - Jd qd) + (I - J^W# J) qdd0,
  // qdd0 descending the side criterion and damping the self-motion (so it stays stable); qd is the input's
  // joint-velocity estimate (device.joints.velocity). Real-time safe.
  virtual JointVector task_acceleration(const DeviceState& device, const ChainState& chain,
                                        const model::TaskVector& xdd_minus_bias) noexcept = 0;
  // Torque level at the measured state: the dynamically consistent null-space torque
  //   (I - J^T J^{M#T}) tau0, tau0 = -k grad H - d M qd,
  // which adds no task acceleration. rows: task rows. Real-time safe.
  virtual JointVector null_space_torque(const DeviceState& device, const ChainState& chain, int rows) noexcept = 0;
};

}  // namespace hapticd
