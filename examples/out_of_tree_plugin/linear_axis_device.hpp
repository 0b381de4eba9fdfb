// Example device: a simulated linear axis (a carriage of mass m on a rail with viscous friction, driven by the
// commanded force). A hardware driver has the same shape: configure() opens the connection and describes the
// joints, enable() powers the drive with zero force, read() and write() talk to it each cycle, disable() powers
// it off.
#pragma once
#include <hapticd/plugin.hpp>

namespace example {

class LinearAxisDevice final : public hapticd::Device {
 public:
  static hapticd::ParameterSchema parameter_schema();

  void configure(const hapticd::Parameters& p, const hapticd::PluginContext& context) override;
  [[nodiscard]] const hapticd::DeviceDescription& description() const override { return description_; }
  hapticd::Outcome enable() override;
  hapticd::Outcome read(const hapticd::CycleTime& cycle, hapticd::DeviceState& state) override;
  hapticd::Outcome write(const hapticd::CycleTime& cycle, const hapticd::JointCommand& command) override;
  void disable() override { force_n_ = 0.0; }
  bool simulated_truth(hapticd::SimulatedTruth& out) const override;

 private:
  hapticd::DeviceDescription description_;
  double mass_kg_ = 1.0, friction_ = 0.0;
  double position_m_ = 0.0, velocity_m_s_ = 0.0, force_n_ = 0.0;
  std::int64_t time_ns_ = -1;  // the physics' time; -1 before the first read
};

}  // namespace example
