#include "session/engine_input_port.hpp"

#include <algorithm>

namespace hapticd::server {

double engine_weight(double age_s, double previous, double period_s, const EngineTiming& timing) noexcept {
  const double late = age_s - timing.deadline_s;
  const double target = late <= 0.0 ? 1.0 : std::clamp(1.0 - late / std::max(timing.fade_s, 1e-9), 0.0, 1.0);
  const double step = period_s / std::max(timing.ramp_in_s, 1e-9);
  return target > previous ? std::min(target, previous + step) : target;
}

void EngineInputPort::take(const CycleTime& cycle, const EngineInput* local) noexcept {
  if (local != nullptr) incoming_ = *local;
  if (local != nullptr || inbox_.take(incoming_)) {  // the owner's newest input (a new owner's after a release)
    input_ = incoming_;
    input_.received_ns = cycle.time_ns;
    seen_ = true;
    released_ = false;
  }
  // After the input: what the inbox held when the release arrived was the released engine's last command (the
  // gate passes no command of its after the release).
  if (ended_.exchange(false, std::memory_order_acq_rel) && seen_) {
    // As if the deadline had passed one cycle ago: the fade starts this cycle.
    input_.received_ns = std::min(
        input_.received_ns, cycle.time_ns - static_cast<std::int64_t>(timing_.deadline_s * 1e9) - cycle.period_ns);
    released_ = true;
  }
  if (!seen_) {
    input_.weight = weight_ = 0.0;
    return;
  }
  const double age = static_cast<double>(cycle.time_ns - input_.received_ns) * 1e-9;
  input_.weight = weight_ = engine_weight(age, weight_, static_cast<double>(cycle.period_ns) * 1e-9, timing_);
  late_ = age > timing_.deadline_s;
}

}  // namespace hapticd::server
