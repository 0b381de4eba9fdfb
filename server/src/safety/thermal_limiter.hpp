#pragma once
// Continuous torque through a thermal model: a first-order model per joint of the winding's heating,
//   d load/dt = ((tau / tau_continuous)^2 - load) / time_constant,
// so load 1 is the steady state at the continuous torque. The torque limit is the peak torque while the load is
// below `derate_from` and falls linearly to the continuous torque as the load reaches 1: a drive can give its
// peak for a while (about time_constant / (peak/continuous)^2 from cold) and its continuous torque for ever.
// Real-time safe after configure().
#include "hapticd/joint_vector.hpp"

namespace hapticd::server {

class ThermalLimiter {
 public:
  // Joints whose continuous torque is not below the peak (or not given) keep the peak limit.
  void configure(const JointVector& peak, const JointVector& continuous, double time_constant_s, double derate_from,
                 double period_s);
  // The limit for this cycle.
  [[nodiscard]] const JointVector& limit() const noexcept { return limit_; }
  // After the command is final: heats the model with it and sets the next cycle's limit.
  void update(const JointVector& torque) noexcept;
  [[nodiscard]] double load(int joint) const noexcept { return load_[joint]; }
  [[nodiscard]] double max_load() const noexcept { return load_.size() > 0 ? load_.maxCoeff() : 0.0; }
  // Some joint is below its peak limit.
  [[nodiscard]] bool derating() const noexcept { return derating_; }

 private:
  JointVector peak_, continuous_, load_, limit_;
  double alpha_ = 0.0;  // period / time constant; 0: off
  double derate_from_ = 0.9;
  bool derating_ = false;
};

}  // namespace hapticd::server
