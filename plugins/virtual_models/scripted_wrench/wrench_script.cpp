#include "wrench_script.hpp"

#include <cmath>
#include <stdexcept>

namespace hapticd::models {

WrenchScript::Signal WrenchScript::parse(const std::string& name) {
  if (name == "constant") return Signal::constant;
  if (name == "sine") return Signal::sine;
  if (name == "chirp") return Signal::chirp;
  if (name == "steps") return Signal::steps;
  throw std::invalid_argument("unknown signal '" + name + "' (constant, sine, chirp, steps)");
}

void WrenchScript::configure(const Settings& s) {
  if (s.signal == Signal::steps && (s.levels.empty() || s.levels.size() > static_cast<std::size_t>(kMaxLevels))) {
    throw std::invalid_argument("steps need 1 to " + std::to_string(kMaxLevels) + " levels, got " +
                                std::to_string(s.levels.size()));
  }
  if (s.signal == Signal::chirp && !(s.chirp_duration_s > 0.0)) {
    throw std::invalid_argument("a chirp needs a positive duration");
  }
  if (s.signal == Signal::steps && !(s.step_s > 0.0)) throw std::invalid_argument("steps need a positive duration");
  signal_ = s.signal;
  direction_ = s.direction;
  start_s_ = s.start_s;
  frequency_hz_ = s.frequency_hz;
  f0_ = s.chirp_start_hz;
  f1_ = s.chirp_end_hz;
  sweep_s_ = s.chirp_duration_s;
  step_s_ = s.step_s;
  level_count_ = static_cast<int>(s.levels.size());
  for (int i = 0; i < level_count_; ++i) levels_[static_cast<std::size_t>(i)] = s.levels[static_cast<std::size_t>(i)];
}

double WrenchScript::signal(double t) const noexcept {
  const double local = t - start_s_;
  if (local < 0.0) return 0.0;
  switch (signal_) {
    case Signal::constant:
      return 1.0;
    case Signal::sine:
      return std::sin(2.0 * M_PI * frequency_hz_ * local);
    case Signal::chirp:
      if (local > sweep_s_) return 0.0;
      return std::sin(2.0 * M_PI * (f0_ * local + 0.5 * (f1_ - f0_) * local * local / sweep_s_));
    case Signal::steps: {
      const auto k = static_cast<long>(std::floor(local / step_s_));
      return levels_[static_cast<std::size_t>(std::min<long>(k, level_count_ - 1))];
    }
  }
  return 0.0;
}

double WrenchScript::frequency_at(double t) const noexcept {
  const double local = t - start_s_;
  if (local < 0.0) return 0.0;
  if (signal_ == Signal::sine) return frequency_hz_;
  if (signal_ == Signal::chirp && local <= sweep_s_) return f0_ + (f1_ - f0_) * local / sweep_s_;
  return 0.0;
}

}  // namespace hapticd::models
