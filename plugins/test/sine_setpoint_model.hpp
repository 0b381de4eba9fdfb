#pragma once
#include "hapticd/virtual_model.hpp"

namespace hapticd::test_plugins {

// Desired handle motion x_d(t) = offset + amplitude sin(2 pi f t) along the world x axis, with its velocity
// and acceleration: an admittance-type target without an operator.
class SineSetpointModel final : public VirtualModel {
 public:
  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const PluginContext& context) override;
  Outcome activate(const VirtualModelInput& current) override;
  Outcome update(const CycleTime& cycle, const VirtualModelInput& input, TaskTarget& target) override;
  void deactivate() override {}

 private:
  double offset_m_ = 0.0;
  double amplitude_m_ = 0.0;
  double frequency_hz_ = 0.0;
};

}  // namespace hapticd::test_plugins
