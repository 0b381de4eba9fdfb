#pragma once
#include "hapticd/chain_signals.hpp"
#include "hapticd/cycle_time.hpp"
#include "hapticd/export.hpp"
#include "hapticd/parameters.hpp"
#include "hapticd/plugin_context.hpp"
#include "hapticd/redundancy_resolution.hpp"
#include "hapticd/return_code.hpp"

namespace hapticd {

// Maps the task-space target to joint space (and resolves redundancy for n > m devices).
// Real-time methods (activate, update) must not throw, allocate, lock or log. The interface does not declare them
// noexcept on purpose: a plugin that throws anyway is contained to its own device (fault plugin_exception, its
// safe mode) instead of terminating the server with every device it drives (docs/plugin-guide.md).
class HAPTICD_API InverseKinematics {
 public:
  virtual ~InverseKinematics();

  // Not real-time safe. Validate parameters (ParameterError names the key) and allocate everything.
  virtual void configure(const Parameters& parameters, const PluginContext& context) = 0;
  // Real-time safe. Start at a cycle boundary from the current joint state.
  virtual ReturnCode activate(const InverseKinematicsInput& current) = 0;
  // Real-time safe.
  virtual ReturnCode update(const CycleTime& cycle, const InverseKinematicsInput& input, JointTarget& target) = 0;
  // Not real-time safe. Called after the plugin has left the loop.
  virtual void deactivate() = 0;
  // The redundancy resolution this plugin offers the chain's controller (after configure), or nullptr.
  virtual RedundancyResolution* redundancy() noexcept { return nullptr; }
};

}  // namespace hapticd
