#pragma once
#include "hapticd/chain_signals.hpp"
#include "hapticd/chain_state.hpp"
#include "hapticd/cycle_time.hpp"
#include "hapticd/engine_input.hpp"
#include "hapticd/export.hpp"
#include "hapticd/parameters.hpp"
#include "hapticd/plugin_context.hpp"
#include "hapticd/render_port.hpp"
#include "hapticd/return_code.hpp"
#include "hapticd/runtime_request.hpp"

namespace hapticd {

// The virtual environment a device renders: admittance type (operator and environment wrench in, desired
// motion out) or impedance type (measured motion in, desired wrench out).
// Real-time methods (activate, update) must not throw, allocate, lock or log, and are not declared noexcept
// (return_code.hpp: the rule for exceptions).
class HAPTICD_API VirtualModel : public RuntimeRequests {
 public:
  ~VirtualModel() override;

  // Not real-time safe. Validate parameters (ParameterError names the key) and allocate everything.
  virtual void configure(const Parameters& parameters, const PluginContext& context) = 0;
  // Real-time safe. Start at a cycle boundary from the current state (for instance: the desired pose starts
  // at the measured pose), so the hand-over does not make the torque jump.
  virtual Outcome activate(const VirtualModelInput& current) = 0;
  // Real-time safe.
  virtual Outcome update(const CycleTime& cycle, const VirtualModelInput& input, TaskTarget& target) = 0;
  // Not real-time safe. Called after the model has left the loop.
  virtual void deactivate() = 0;
};

}  // namespace hapticd
