#pragma once
#include "hapticd/chain_signals.hpp"
#include "hapticd/cycle_time.hpp"
#include "hapticd/export.hpp"
#include "hapticd/parameters.hpp"
#include "hapticd/plugin_context.hpp"
#include "hapticd/return_code.hpp"
#include "hapticd/runtime_request.hpp"

namespace hapticd {

// The virtual environment a device renders: admittance type (operator and environment wrench in, desired
// motion out) or impedance type (measured motion in, desired wrench out).
// Real-time methods (activate, update) must not throw, allocate, lock or log. The interface does not declare them
// noexcept on purpose: a plugin that throws anyway is contained to its own device (fault plugin_exception, its
// safe mode) instead of terminating the server with every device it drives (docs/plugin-guide.md).
class HAPTICD_API VirtualModel {
 public:
  virtual ~VirtualModel();

  // Not real-time safe. Validate parameters (ParameterError names the key) and allocate everything.
  virtual void configure(const Parameters& parameters, const PluginContext& context) = 0;
  // Real-time safe. Start at a cycle boundary from the current state (for instance: the desired pose starts
  // at the measured pose), so the hand-over does not make the torque jump.
  virtual ReturnCode activate(const VirtualModelInput& current) = 0;
  // Real-time safe.
  virtual ReturnCode update(const CycleTime& cycle, const VirtualModelInput& input, TaskTarget& target) = 0;
  // Not real-time safe. Called after the model has left the loop.
  virtual void deactivate() = 0;
  // Not real-time safe, any server thread (runtime_request.hpp): a tunable parameter was set. `parameters` holds
  // the value in effect of every parameter, the new one checked against the schema. Read the tunable ones as
  // configure() does and hand them to the loop; throw ParameterError to refuse (the old values stay). The
  // default refuses: a plugin that declares tunable parameters overrides it.
  virtual void tune(const Parameters& parameters);
  // Not real-time safe, any server thread (runtime_request.hpp): a command of the plugin's own (a name the
  // schema does not declare); `values` its numbers. The default refuses.
  virtual RuntimeReply handle_request(std::string_view name, const std::vector<double>& values);
};

}  // namespace hapticd
