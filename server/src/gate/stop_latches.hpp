#pragma once
// The E-stops that hold one device, each until the one who made it releases it (docs/safety.md, "Who may
// recover a stopped device"). Anyone may stop a device; a stop requested through any door latches under the
// identity of its requester - the peer, and the client id it declared - and only that identity releases it: the
// same peer, or, once that peer is gone (a one-shot `hapticctl estop` has left the domain, a connection closed), a
// client under the same id. Lockout-tagout: every stopper releases its own stop; the device recovers once none holds.
// Bounded: past kMax stoppers a further stop still stops the device and marks the latches overflowed: then no
// request can recover it (only a restart).
#include <array>
#include <cstddef>
#include <functional>
#include <string>
#include <string_view>

#include "gate/peer.hpp"

namespace hapticd::server {

struct Stopper {
  Sender sender;       // the peer and the channel of its stop request (the channel gone: the peer left)
  std::string client;  // the client id the stop request declared
};
// Whether the channel a stop was requested through is gone (the door's presence).
using GoneCheck = std::function<bool(const Sender&)>;

class StopLatches {
 public:
  static constexpr std::size_t kMax = 16;

  // A stop request from `who` (the same identity twice holds one latch).
  void add(const Stopper& who);
  // Whether `peer` under `client` is the identity of a stopper; gone(sender) tells whether a stopper has left.
  [[nodiscard]] bool held_by(const PeerId& peer, std::string_view client, const GoneCheck& gone) const;
  // Releases the latches of that identity; true if it held any.
  bool release(const PeerId& peer, std::string_view client, const GoneCheck& gone);
  [[nodiscard]] bool empty() const noexcept { return count_ == 0 && !overflowed_; }
  [[nodiscard]] bool overflowed() const noexcept { return overflowed_; }
  // The client ids of the stoppers, for a refusal ("'operator', 'console'").
  [[nodiscard]] std::string holders() const;

 private:
  [[nodiscard]] bool matches(const Stopper& s, const PeerId& peer, std::string_view client,
                             const GoneCheck& gone) const;

  std::array<Stopper, kMax> stoppers_{};
  std::size_t count_ = 0;
  bool overflowed_ = false;
};

}  // namespace hapticd::server
