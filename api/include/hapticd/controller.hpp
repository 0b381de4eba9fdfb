#pragma once
#include "hapticd/chain_signals.hpp"
#include "hapticd/cycle_time.hpp"
#include "hapticd/export.hpp"
#include "hapticd/parameters.hpp"
#include "hapticd/plugin_context.hpp"
#include "hapticd/return_code.hpp"
#include "hapticd/runtime_request.hpp"

namespace hapticd {

// Turns the targets of the chain into joint torques.
// Real-time methods (activate, update) must not throw, allocate, lock or log, and are not declared noexcept
// (return_code.hpp: the rule for exceptions).
class HAPTICD_API Controller : public RuntimeRequests {
 public:
  ~Controller() override;

  // Not real-time safe. Validate parameters (ParameterError names the key) and allocate everything.
  virtual void configure(const Parameters& parameters, const PluginContext& context) = 0;
  // Real-time safe. Start at a cycle boundary from the current state and the last torque command that reached
  // the drives (bumpless transfer: the first update() should not jump away from it).
  virtual Outcome activate(const ControllerInput& current, const JointCommand& last_command) = 0;
  // Real-time safe.
  virtual Outcome update(const CycleTime& cycle, const ControllerInput& input, JointCommand& command) = 0;
  // Not real-time safe. Called after the controller has left the loop.
  virtual void deactivate() = 0;
};

}  // namespace hapticd
