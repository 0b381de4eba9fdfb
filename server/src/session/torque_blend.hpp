#pragma once
// A torque step that fades out. After a scheme switch or a recovery the chain's first command may differ from
// the torque the drives hold; the difference fades out linearly over the ramp, so the drives see no step.
// Pending: the difference is taken against the next command of the chain; fading: it is being added.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "hapticd/demand.hpp"
#include "hapticd/joint_vector.hpp"

namespace hapticd::server {

class TorqueBlend {
 public:
  explicit TorqueBlend(std::int64_t ramp_cycles = 1) : ramp_cycles_(std::max<std::int64_t>(1, ramp_cycles)) {}

  // From the next command on, fade from `held` (the torque the drives hold) to the chain's commands.
  void begin(const JointVector& held) noexcept {
    offset_ = held;
    phase_ = Phase::pending;
  }
  void cancel() noexcept { phase_ = Phase::none; }
  // The chain's command of this cycle, with what is left of the difference added.
  void apply(JointVector& command) noexcept {
    if (phase_ == Phase::none) return;
    if (phase_ == Phase::pending) {
      HAPTICD_DEMAND(offset_.size() == command.size());  // the same device's joints
      offset_ -= command;
      phase_ = Phase::fading;
      left_ = ramp_cycles_;
    }
    command += offset_ * (static_cast<double>(left_) / static_cast<double>(ramp_cycles_));
    if (--left_ == 0) phase_ = Phase::none;
  }
  [[nodiscard]] bool active() const noexcept { return phase_ != Phase::none; }

 private:
  enum class Phase : std::uint8_t { none, pending, fading };
  Phase phase_ = Phase::none;
  JointVector offset_;
  std::int64_t ramp_cycles_;
  std::int64_t left_ = 0;
};

}  // namespace hapticd::server
