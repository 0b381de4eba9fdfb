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
// Real-time methods (activate, update) must not throw, allocate, lock or log. The interface does not declare them
// noexcept on purpose: a plugin that throws anyway is contained to its own device (fault plugin_exception, its
// safe mode) instead of terminating the server with every device it drives (docs/plugin-guide.md).
class HAPTICD_API Controller {
 public:
  virtual ~Controller();

  // Not real-time safe. Validate parameters (ParameterError names the key) and allocate everything.
  virtual void configure(const Parameters& parameters, const PluginContext& context) = 0;
  // Real-time safe. Start at a cycle boundary from the current state and the last torque command that reached
  // the drives (bumpless transfer: the first update() should not jump away from it).
  virtual ReturnCode activate(const ControllerInput& current, const JointCommand& last_command) = 0;
  // Real-time safe.
  virtual ReturnCode update(const CycleTime& cycle, const ControllerInput& input, JointCommand& command) = 0;
  // Not real-time safe. Called after the controller has left the loop.
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
