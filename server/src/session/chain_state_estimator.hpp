#pragma once
// Phase (a)'s estimate for one device (docs/architecture.md, "One cycle"): from the measured state, the chain
// state every plugin of the chain reads - the one joint-velocity estimate (written into the DeviceState the
// chain sees) (the device's own measurement, or
// filtered encoder differences over the time that really passed) and, when the device names a robot model, the
// model terms of the cycle (forward kinematics, Jacobian, mass matrix, Coriolis and gravity terms), the handle's
// pose and twist, and the operator's wrench from the force/torque sensor moved to the handle. A handle device
// (hapticd/handle.hpp) has no model: its axes are filled from the handle it reports, turned into the world.
#include <cstdint>
#include <memory>

#include "hapticd/chain_state.hpp"
#include "hapticd/device.hpp"
#include "hapticd/model/model_data.hpp"
#include "hapticd/model/robot_model.hpp"
#include "hapticd/signal/differentiator.hpp"

namespace hapticd::server {

class ChainStateEstimator {
 public:
  // robot: the device's parsed robot model (DeviceChain::robot_model, checked against the device), or null.
  ChainStateEstimator(const DeviceDescription& description, std::shared_ptr<const model::RobotModel> robot,
                      double period_s);
  ChainStateEstimator(const ChainStateEstimator&) = delete;
  ChainStateEstimator& operator=(const ChainStateEstimator&) = delete;

  // Real-time safe. Writes the one joint-velocity estimate into state.joints.velocity (the device's own when it
  // reports velocity, else filtered position differences) and computes the chain state from it. restart: the
  // velocity estimate starts from this sample (zero, unless the device measures velocity) - when the chain
  // (re)activates from the measured state.
  void estimate(DeviceState& state, std::int64_t time_ns, std::int64_t period_ns, bool restart) noexcept;
  // The next estimate restarts the velocity estimate (the device was activated again).
  void reset() noexcept { ready_ = false; }

  [[nodiscard]] const ChainState& state() const noexcept { return state_; }
  ChainState& state() noexcept { return state_; }  // the chain adds its own findings (output saturated)
  // The gravity torque of the latest estimate, nullptr without a robot model.
  [[nodiscard]] const JointVector* gravity_torque() const noexcept {
    return model_data_ ? &model_data_->gravity_torque : nullptr;
  }
  [[nodiscard]] bool has_model() const noexcept { return robot_ != nullptr; }

  // Cut-off of the joint-velocity estimate for devices without velocity measurement (encoder differences).
  static constexpr double kVelocityFilterHz = 100.0;

 private:
  bool measures_velocity_;
  bool handle_device_;
  HandleDescription handle_;
  Eigen::Isometry3d base_;
  std::shared_ptr<const model::RobotModel> robot_;
  std::unique_ptr<model::ModelData> model_data_;
  int sensor_frame_ = -1;
  signal::Differentiator<JointVector> differentiator_;
  std::int64_t differentiated_ns_ = 0;  // loop time of the differentiator's last sample
  bool ready_ = false;
  ChainState state_;
};

}  // namespace hapticd::server
