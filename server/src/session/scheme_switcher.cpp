#include "session/scheme_switcher.hpp"

#include <utility>

#include "hapticd/demand.hpp"
#include "loader/plugin_deactivation.hpp"

namespace hapticd::server {

SchemeSwitcher::SchemeSwitcher(std::vector<SchemeChain>& schemes)
    : schemes_(schemes), state_(std::vector<std::atomic<State>>(schemes.size())) {
  for (auto& s : state_) s.store(State::idle);
}

bool SchemeSwitcher::request(std::string_view name) {
  for (std::size_t i = 0; i < schemes_.size(); ++i) {
    if (schemes_[i].name == name) {
      requested_.store(static_cast<int>(i), std::memory_order_release);
      return true;
    }
  }
  return false;
}

const std::string& SchemeSwitcher::active_name() const noexcept {
  static const std::string none;
  return schemes_.empty() ? none : schemes_[active_index()].name;
}

void SchemeSwitcher::entered() noexcept { state_[active_index()].store(State::active, std::memory_order_release); }

void SchemeSwitcher::left() noexcept {
  auto& s = state_[active_index()];
  if (s.load(std::memory_order_relaxed) == State::active) s.store(State::leaving, std::memory_order_release);
}

bool SchemeSwitcher::active_idle() const noexcept {
  return state_[active_index()].load(std::memory_order_acquire) == State::idle;
}

SchemeChain* SchemeSwitcher::wanted() noexcept {
  const int wanted = requested_.load(std::memory_order_acquire);
  if (wanted == active_.load(std::memory_order_relaxed)) return nullptr;
  const auto w = static_cast<std::size_t>(wanted);
  if (state_[w].load(std::memory_order_acquire) != State::idle) return nullptr;  // still leaving: wait for service()
  return &schemes_[w];
}

void SchemeSwitcher::switched() noexcept {
  const int wanted = requested_.load(std::memory_order_relaxed);
  HAPTICD_DEMAND(wanted != active_.load(std::memory_order_relaxed));  // only after wanted() offered a scheme
  state_[active_index()].store(State::leaving, std::memory_order_release);
  state_[static_cast<std::size_t>(wanted)].store(State::active, std::memory_order_release);
  active_.store(wanted, std::memory_order_release);
  switches_.fetch_add(1, std::memory_order_relaxed);
}

void SchemeSwitcher::refused_switch() noexcept {
  const int wanted = requested_.load(std::memory_order_relaxed);
  HAPTICD_DEMAND(wanted != active_.load(std::memory_order_relaxed));
  refused_.fetch_add(1, std::memory_order_relaxed);
  state_[static_cast<std::size_t>(wanted)].store(State::leaving, std::memory_order_release);
  // Keep running the old scheme, unless another request came in meanwhile.
  int expected = wanted;
  requested_.compare_exchange_strong(expected, active_.load(std::memory_order_relaxed), std::memory_order_acq_rel);
}

void SchemeSwitcher::service(bool all) {
  for (std::size_t i = 0; i < schemes_.size(); ++i) {
    const State s = state_[i].load(std::memory_order_acquire);
    if (s == State::idle || (s == State::active && !all)) continue;
    SchemeChain& scheme = schemes_[i];
    const auto keep = [&](const std::string& error) {
      if (!error.empty()) errors_.push_back("scheme '" + scheme.name + "', " + error);
    };
    keep(deactivate_plugin(scheme.controller, "controller"));
    if (scheme.inverse_kinematics) keep(deactivate_plugin(*scheme.inverse_kinematics, "inverse kinematics"));
    if (scheme.virtual_model) keep(deactivate_plugin(*scheme.virtual_model, "virtual model"));
    state_[i].store(State::idle, std::memory_order_release);
  }
}

std::vector<std::string> SchemeSwitcher::take_errors() { return std::exchange(errors_, {}); }

}  // namespace hapticd::server
