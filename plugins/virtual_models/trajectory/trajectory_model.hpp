#pragma once
// The trajectory model ("trajectory"): the desired handle motion played over time, a motion source for
// admittance display (its inner loop tracks it; no operator wrench enters). The path is a Profile (constant, step,
// ramp, sine or shuttle: constant-acceleration and constant-velocity phases) relative to the handle's position at
// activation, in world axes; the orientation is held. Position, velocity and acceleration are the profile's own
// (analytic), so an inner loop with acceleration feedforward gets the path's true acceleration. The evaluation
// suite's tracking experiment (the thesis's appendix B) plays its path with it.
#include "hapticd/virtual_model.hpp"
#include "profile.hpp"

namespace hapticd::models {

class TrajectoryModel final : public VirtualModel {
 public:
  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const PluginContext& context) override;
  Outcome activate(const VirtualModelInput& current) override;
  Outcome update(const CycleTime& cycle, const VirtualModelInput& input, TaskTarget& target) override;
  void deactivate() override {}

 private:
  Profile path_;
  Pose start_;
  bool started_ = false;
  std::int64_t start_ns_ = 0;
};

}  // namespace hapticd::models
