#pragma once
#include "hapticd/chain_signals.hpp"
#include "hapticd/cycle_time.hpp"
#include "hapticd/export.hpp"
#include "hapticd/parameters.hpp"
#include "hapticd/plugin_context.hpp"
#include "hapticd/redundancy_resolution.hpp"
#include "hapticd/return_code.hpp"
#include "hapticd/runtime_request.hpp"

namespace hapticd {

// Maps the task-space target to joint space (and resolves redundancy for n > m devices).
// Real-time methods (activate, update) must not throw, allocate, lock or log, and are not declared noexcept
// (return_code.hpp: the rule for exceptions).
class HAPTICD_API InverseKinematics : public RuntimeRequests {
 public:
  ~InverseKinematics() override;

  // Not real-time safe. Validate parameters (ParameterError names the key) and allocate everything.
  virtual void configure(const Parameters& parameters, const PluginContext& context) = 0;
  // Real-time safe. Start at a cycle boundary from the current joint state.
  virtual Outcome activate(const InverseKinematicsInput& current) = 0;
  // Real-time safe.
  virtual Outcome update(const CycleTime& cycle, const InverseKinematicsInput& input, JointTarget& target) = 0;
  // Not real-time safe. Called after the plugin has left the loop.
  virtual void deactivate() = 0;
  // The redundancy resolution this plugin offers the chain's controller (after configure), or nullptr.
  virtual RedundancyResolution* redundancy() noexcept { return nullptr; }
};

}  // namespace hapticd
