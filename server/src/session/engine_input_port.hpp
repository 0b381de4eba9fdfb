#pragma once
// The rendering engine's input as a device's chain sees it (docs/dds-interface.md, "Staleness and
// reconnection"): the newest input from the DDS side through a lock-free hand-off, weighted by how old it is -
// fresh until the deadline, then a linear fade to zero; input that (re)starts after a silence ramps in, so an
// engine that connects or reconnects causes no force step. The weight is a pure function (engine_weight).
// An engine that releases the device cleanly (end()) fades out as after a missed deadline, without being stale:
// it did nothing wrong.
#include <atomic>
#include <cstdint>

#include "hapticd/device.hpp"
#include "hapticd/engine_input.hpp"
#include "hapticd/realtime/latest_value.hpp"

namespace hapticd::server {

struct EngineTiming {
  double deadline_s = 0.05;  // input older than this fades out ...
  double fade_s = 0.02;      // ... over this time
  double ramp_in_s = 0.1;    // input starting after a silence ramps in over this time
};

// The weight this cycle of engine input that is `age_s` old, given the previous cycle's weight. Pure.
[[nodiscard]] double engine_weight(double age_s, double previous, double period_s, const EngineTiming& timing) noexcept;

class EngineInputPort {
 public:
  explicit EngineInputPort(EngineTiming timing) : timing_(timing) {}

  // Any thread (the DDS command listener): the engine's newest input.
  void publish(const EngineInput& input) { inbox_.publish(input); }
  // Any thread: the engine released the device; its input fades out from the next cycle on, not stale.
  void end() noexcept { ended_.store(true, std::memory_order_release); }
  // Loop thread: takes the newest input, if any, and weights it for this cycle. `local`: the input made in this
  // cycle by the loop itself (the teleoperation link's force), taken instead of the inbox's.
  void take(const CycleTime& cycle, const EngineInput* local = nullptr) noexcept;
  // Loop thread: after a recovery the input ramps in again, as after a silence.
  void restart() noexcept {
    seen_ = false;
    weight_ = 0.0;
  }

  [[nodiscard]] const EngineInput& input() const noexcept { return input_; }
  // The engine missed its deadline (its input is fading or gone).
  [[nodiscard]] bool stale() const noexcept { return seen_ && late_ && !released_; }

 private:
  EngineTiming timing_;
  realtime::LatestValue<EngineInput> inbox_;
  EngineInput incoming_, input_;
  bool seen_ = false;
  double weight_ = 0.0;
  bool late_ = false;
  bool released_ = false;  // the input fading is a released engine's
  std::atomic<bool> ended_{false};
};

}  // namespace hapticd::server
