#pragma once
// Model-based compensation of sliding friction, per joint ([U06] methods 1; the same `+ h` in the inner loops of
// admittance display, methods 2):
//   h_i = fraction * s(qd_i) * f_i(|qd_i|, t_i),   s(qd) = clamp(qd / v_s, -1, 1),
// with f_i the joint's FrictionModel and t_i its static load torque. The smooth sign keeps quantised
// velocities from chattering the compensation; the fraction below 1 guards against over-compensation.
// Friction at rest is left to the impedance controller's stiction compensator. Real-time safe; the models can be
// replaced in the loop (adaptive re-tuning) by a plain copy.
#include <array>

#include "hapticd/joint_vector.hpp"
#include "hapticd/model/friction_model.hpp"

namespace hapticd::controllers {

using FrictionModels = std::array<model::FrictionModel, kMaxJoints>;

class FrictionCompensation {
 public:
  void configure(const FrictionModels& models, double fraction, double smooth_velocity) noexcept {
    models_ = models;
    fraction_ = fraction;
    smooth_velocity_ = smooth_velocity;
  }
  void set_models(const FrictionModels& models) noexcept { models_ = models; }
  [[nodiscard]] const FrictionModels& models() const noexcept { return models_; }

  // Compensation torque of joint i at velocity qd and load torque t.
  [[nodiscard]] double torque(int i, double velocity, double load_torque) const noexcept;
  // Load-dependent friction magnitude of joint i beyond its load-free curve.
  [[nodiscard]] double load_part(int i, double load_torque) const noexcept;

 private:
  FrictionModels models_{};
  double fraction_ = 0.8;
  double smooth_velocity_ = 0.05;
};

}  // namespace hapticd::controllers
