// Example virtual model of impedance type: a horizontal wall under the handle. It reads the measured handle
// motion and answers the wall's force, which goes through the render port's limits.
#pragma once
#include <hapticd/plugin.hpp>

namespace example {

class WallModel final : public hapticd::VirtualModel {
 public:
  static hapticd::ParameterSchema parameter_schema();

  void configure(const hapticd::Parameters& p, const hapticd::PluginContext& context) override;
  hapticd::Outcome activate(const hapticd::VirtualModelInput& current) override;
  hapticd::Outcome update(const hapticd::CycleTime& cycle, const hapticd::VirtualModelInput& in,
                          hapticd::TaskTarget& target) override;
  void deactivate() override {}

 private:
  double height_m_ = 0.0, stiffness_ = 0.0, damping_ = 0.0;
};

}  // namespace example
