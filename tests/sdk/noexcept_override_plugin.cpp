// The plugin SDK's rule for exceptions (hapticd/return_code.hpp), checked where plugins are described: a plugin
// whose real-time method is declared noexcept does not compile (the test expects describe_plugin's message).
// Compiled with -DHAPTICD_RULE_KEPT, the same plugin without noexcept compiles: the check is not a false alarm.
#include "hapticd/plugin.hpp"

#ifdef HAPTICD_RULE_KEPT
#define HAPTICD_TEST_NOEXCEPT
#else
#define HAPTICD_TEST_NOEXCEPT noexcept
#endif

namespace {

class NoexceptController final : public hapticd::Controller {
 public:
  static hapticd::ParameterSchema parameter_schema() { return {}; }
  void configure(const hapticd::Parameters&, const hapticd::PluginContext&) override {}
  hapticd::Outcome activate(const hapticd::ControllerInput&, const hapticd::JointCommand&) override {
    return hapticd::Outcome::success();
  }
  hapticd::Outcome update(const hapticd::CycleTime&, const hapticd::ControllerInput&,
                          hapticd::JointCommand&) HAPTICD_TEST_NOEXCEPT override {
    return hapticd::Outcome::success();
  }
  void deactivate() override {}
};

}  // namespace

HAPTICD_PLUGIN_LIBRARY(hapticd::describe_plugin<NoexceptController>("noexcept_controller", "1", "the rule's test"))
