#pragma once
// The sliding-friction compensation's parameters, shared by every controller that compensates joint friction
// (impedance display's `+ h` in [U06] methods 1, admittance display's inner loops' `+ h` in methods 2):
// friction_compensation, friction_file, friction_polynomial, friction_load, friction_velocity_max,
// friction_smooth_velocity, friction_fraction. Declaring and configuring run at configure time (file access);
// SlidingFrictionTerm::add is the real-time part.
#include "friction_compensation.hpp"
#include "hapticd/chain_state.hpp"
#include "hapticd/parameters.hpp"
#include "hapticd/plugin_context.hpp"

namespace hapticd::controllers {

void declare_friction_parameters(ParameterSchema& schema);

// The per-joint models (the friction file's, relative to the session file, or the polynomial for every joint)
// and the fraction and smoothing, into `compensation`. Throws ParameterError naming the key on a bad file.
void configure_friction_compensation(const Parameters& p, const PluginContext& context, int dof,
                                     FrictionCompensation& compensation);

// The `+ h` term of a controller: the model's sliding friction in each joint's direction of motion, when the
// session switched it on (friction_compensation), else nothing.
class SlidingFrictionTerm {
 public:
  void configure(const Parameters& p, const PluginContext& context);
  [[nodiscard]] bool enabled() const noexcept { return enabled_; }
  // torque += h(qd, t) for every joint, t its static load torque: gravity and the operator's wrench over the
  // task rows (the chain's model terms). Real-time safe.
  void add(const ChainState& chain, const JointVector& velocity, int rows, JointVector& torque) const noexcept;

 private:
  bool enabled_ = false;
  FrictionCompensation compensation_;
};

}  // namespace hapticd::controllers
