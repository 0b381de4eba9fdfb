#pragma once
// Which engine commands a device accepts: well-formed, finite and bounded content (dds/command_validation),
// from the device's owner, in order, and fresh by the sample's source timestamp. Rejected commands are counted
// per reason and never reach the loop. Used by the gate under its device lock (not thread-safe); it knows no
// transport.
//
// Ownership is bound to a peer (gate/peer.hpp: a DDS participant, a socket connection, the link), not to the
// client id a message declares: a claim records the peer that sent it, commands are accepted only from that peer
// (and under the claim's client id), and serial numbers strictly increase per channel (a DDS writer; a new claim
// restarts them). Another process that writes under the owner's id is "not the owner" (docs/safety.md,
// "Ownership").
#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "gate/peer.hpp"
#include "hapticd/dds/command_validation.hpp"

namespace hapticd::server {

class CommandGate {
 public:
  CommandGate(dds::CommandBounds bounds, double max_sample_age_s)
      : bounds_(bounds), max_age_ns_(static_cast<std::int64_t>(max_sample_age_s * 1e9)) {}

  // true when `peer` (as `client`) now owns the device: it was free, or already that peer's
  // under the same client id.
  bool claim(std::string_view client, const PeerId& peer);
  // Whether claim(client, peer) would succeed now (the one rule both use).
  [[nodiscard]] bool may_claim(std::string_view client, const PeerId& peer) const noexcept;
  // true when `peer` owned the device and released it.
  bool release(const PeerId& peer);
  void release_any();
  [[nodiscard]] bool owned_by(const PeerId& peer) const noexcept { return !owner_.empty() && owner_peer_ == peer; }
  [[nodiscard]] const std::string& owner() const noexcept { return owner_; }  // the claim's client id ("": free)
  [[nodiscard]] const PeerId& owner_peer() const noexcept { return owner_peer_; }

  struct Verdict {
    bool accepted = false;
    dds::RejectReason reason = dds::RejectReason::other;
  };
  // source_ns: the sample's source timestamp, now_ns: the receiving wall clock (both ns since the epoch).
  Verdict admit(const hapticd_msg_EngineCommand& command, const Sender& sender, std::int64_t source_ns,
                std::int64_t now_ns);

  [[nodiscard]] std::uint64_t received() const noexcept { return received_; }
  [[nodiscard]] std::uint64_t accepted() const noexcept { return accepted_; }
  [[nodiscard]] const std::array<std::uint64_t, dds::kRejectReasons>& rejected() const noexcept { return rejected_; }
  [[nodiscard]] std::uint64_t rejected_total() const noexcept;

  // The owner's channels whose serials are remembered (an owner with more forgets the least recent).
  static constexpr std::size_t kWriters = 8;

 private:
  Verdict reject(dds::RejectReason reason);
  // The last serial accepted from `writer` (0: none yet); makes room for it if it is new.
  std::uint64_t& last_serial_of(std::uint64_t channel);

  struct WriterSerial {
    std::uint64_t channel = 0;
    std::uint64_t serial = 0;
    std::uint64_t used = 0;
  };

  dds::CommandBounds bounds_;
  std::int64_t max_age_ns_;
  std::string owner_;
  PeerId owner_peer_;
  std::array<WriterSerial, kWriters> serials_{};
  std::uint64_t clock_ = 0;
  std::uint64_t received_ = 0, accepted_ = 0;
  std::array<std::uint64_t, dds::kRejectReasons> rejected_{};
};

}  // namespace hapticd::server
