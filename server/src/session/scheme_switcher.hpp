#pragma once
// A device's control schemes and which one runs. A request from any thread names the next scheme; the loop
// switches at a cycle boundary once that scheme is idle; a scheme that left the loop is deactivated off the loop
// by service(), and only then can it run again. Each scheme is idle (deactivated), active (in the loop) or
// leaving (left the loop, waiting for service()). The switcher activates no plugin itself: the loop asks it which
// scheme to activate and tells it the outcome, so the state machine is the same whatever the plugins do.
#include <atomic>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "hapticd/demand.hpp"
#include "session/device_chain.hpp"

namespace hapticd::server {

class SchemeSwitcher {
 public:
  // schemes[0] runs first; the switcher keeps a reference: the schemes outlive it.
  explicit SchemeSwitcher(std::vector<SchemeChain>& schemes);

  // Any thread: asks for the scheme `name` from the next cycle on; false if there is no such scheme.
  bool request(std::string_view name);
  // Any thread: the scheme running now ("" without schemes), its index, and the switches made or refused.
  [[nodiscard]] const std::string& active_name() const noexcept;
  [[nodiscard]] std::size_t active_index() const noexcept {
    return static_cast<std::size_t>(active_.load(std::memory_order_acquire));
  }
  [[nodiscard]] std::uint64_t switches() const noexcept { return switches_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t refused() const noexcept { return refused_.load(std::memory_order_relaxed); }

  // Loop thread. The scheme that runs (or is to be activated when the chain starts or recovers).
  [[nodiscard]] SchemeChain& active() noexcept {
    HAPTICD_DEMAND(!schemes_.empty());  // a device without schemes never runs its chain
    return schemes_[active_index()];
  }
  // The chain activated active(): it is in the loop.
  void entered() noexcept;
  // The chain left the loop (a fault, a stop): active() waits for service() before it can be activated again.
  void left() noexcept;
  // Whether active() has been deactivated since it left (a recovery waits for it).
  [[nodiscard]] bool active_idle() const noexcept;
  // The requested scheme when it differs from the running one and is idle (ready to activate), else nullptr.
  [[nodiscard]] SchemeChain* wanted() noexcept;
  // wanted() activated: it runs from now on, the old scheme leaves.
  void switched() noexcept;
  // wanted() failed to activate: the old scheme runs on and the request is dropped; whatever parts of the wanted
  // scheme activated are deactivated by service().
  void refused_switch() noexcept;

  // Not the loop thread: deactivates the schemes that left the loop. all: every scheme, the loop has stopped.
  // A plugin whose deactivate() throws is taken out all the same (its scheme becomes idle) and the other
  // plugins are deactivated; what it threw waits in take_errors().
  void service(bool all = false);
  // The thread that calls service(): what plugins threw as they were deactivated, since the last call.
  std::vector<std::string> take_errors();

 private:
  enum class State : std::uint8_t { idle, active, leaving };
  std::vector<SchemeChain>& schemes_;
  std::vector<std::atomic<State>> state_;
  std::vector<std::string> errors_;  // service()'s thread only
  std::atomic<int> active_{0};
  std::atomic<int> requested_{0};
  std::atomic<std::uint64_t> switches_{0};
  std::atomic<std::uint64_t> refused_{0};
};

}  // namespace hapticd::server
