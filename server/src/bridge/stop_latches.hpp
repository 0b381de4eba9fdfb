#pragma once
// The E-stops that hold one device, each until the one who made it releases it (docs/safety.md, "Who may
// recover a stopped device"). Anyone may stop a device; a stop requested over DDS latches under the identity of
// its requester - the participant, and the client id it declared - and only that identity releases it: the
// same participant, or, once that participant has left the domain (a one-shot `hapticctl estop`), a client
// under the same id. Lockout-tagout: every stopper releases its own stop; the device recovers once none holds.
// Bounded: past kMax stoppers a further stop still stops the device and marks the latches overflowed: then no
// request over DDS can recover it (only a restart).
#include <dds/dds.h>

#include <array>
#include <cstddef>
#include <functional>
#include <string>
#include <string_view>

#include "bridge/peer_directory.hpp"

namespace hapticd::server {

struct Stopper {
  PeerId participant;
  std::string client;                // the client id the stop request declared
  dds_instance_handle_t writer = 0;  // its request writer (no longer matched: the participant left)
};

class StopLatches {
 public:
  static constexpr std::size_t kMax = 16;

  // A stop request from `who` (the same identity twice holds one latch).
  void add(const Stopper& who);
  // Whether `participant` under `client` is the identity of a stopper; writer_gone(writer) tells whether a
  // stopper's participant has left.
  [[nodiscard]] bool held_by(const PeerId& participant, std::string_view client,
                             const std::function<bool(dds_instance_handle_t)>& writer_gone) const;
  // Releases the latches of that identity; true if it held any.
  bool release(const PeerId& participant, std::string_view client,
               const std::function<bool(dds_instance_handle_t)>& writer_gone);
  [[nodiscard]] bool empty() const noexcept { return count_ == 0 && !overflowed_; }
  [[nodiscard]] bool overflowed() const noexcept { return overflowed_; }
  // The client ids of the stoppers, for a refusal ("'operator', 'console'").
  [[nodiscard]] std::string holders() const;

 private:
  [[nodiscard]] bool matches(const Stopper& s, const PeerId& participant, std::string_view client,
                             const std::function<bool(dds_instance_handle_t)>& writer_gone) const;

  std::array<Stopper, kMax> stoppers_{};
  std::size_t count_ = 0;
  bool overflowed_ = false;
};

}  // namespace hapticd::server
