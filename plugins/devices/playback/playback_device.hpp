#pragma once
// The playback device: replays a recording (hapticd --record, docs/recording.md) as if the recorded device were
// there - its joint positions, velocities and efforts and its force/torque sensor's readings, cycle by cycle on
// the loop's clock (interpolated where the rates differ) - so that engines, virtual models, control schemes and
// the tools run against a recorded session, repeatably. Commands are taken and dropped: nothing moves.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "hapticd/device.hpp"

namespace hapticd::playback {

class PlaybackDevice final : public Device {
 public:
  enum class AtEnd : std::uint8_t { hold, loop, fault };

  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const PluginContext& context) override;
  [[nodiscard]] const DeviceDescription& description() const override { return description_; }
  Outcome enable() override;
  Outcome read(const CycleTime& cycle, DeviceState& state) override;
  Outcome write(const CycleTime& cycle, const JointCommand& command) override;
  void disable() override {}

  // The recording's length on its own clock [s] (last cycle's time minus the first's).
  [[nodiscard]] double duration_s() const noexcept { return times_.empty() ? 0.0 : times_.back(); }

 private:
  // The row at or before recording time t (times_ ascending), or 0.
  [[nodiscard]] std::size_t row_at(double t) const noexcept;

  DeviceDescription description_;
  int dof_ = 0;
  std::vector<double> times_;                                  // from 0, one per recorded cycle
  std::vector<double> position_, velocity_, effort_, wrench_;  // rows of dof_ (wrench: 6)
  bool replay_wrench_ = false;
  double speed_ = 1.0;
  double start_s_ = 0.0;
  AtEnd at_end_ = AtEnd::hold;
  std::int64_t first_ns_ = -1;  // the loop time of the first read after enable()
};

}  // namespace hapticd::playback
