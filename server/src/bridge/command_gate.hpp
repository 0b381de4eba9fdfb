#pragma once
// Which engine commands a device accepts: well-formed, finite and bounded content (dds/command_validation),
// from the device's owner, in order, and fresh by the sample's source timestamp. Rejected commands are counted
// per reason and never reach the loop. Used by the DDS bridge under its device lock (not thread-safe).
//
// Ownership is bound to a DDS participant (PeerDirectory), not to the client id a message declares: a claim
// records the participant whose writer sent it, commands are accepted only from writers of that participant
// (and under the claim's client id), and serial numbers strictly increase per writer (a new claim restarts
// them). Another process that writes under the owner's id is "not the owner" (docs/safety.md, "Ownership").
#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "bridge/peer_directory.hpp"
#include "hapticd/dds/command_validation.hpp"

namespace hapticd::server {

// Who sent a sample: the writer (its publication handle) and the participant it belongs to.
struct Sender {
  PeerId participant;
  dds_instance_handle_t writer = 0;
};

class CommandGate {
 public:
  CommandGate(dds::CommandBounds bounds, double max_sample_age_s)
      : bounds_(bounds), max_age_ns_(static_cast<std::int64_t>(max_sample_age_s * 1e9)) {}

  // true when `participant` (as `client`) now owns the device: it was free, or already that participant's
  // under the same client id.
  bool claim(std::string_view client, const PeerId& participant);
  // Whether claim(client, participant) would succeed now (the one rule both use).
  [[nodiscard]] bool may_claim(std::string_view client, const PeerId& participant) const noexcept;
  // true when `participant` owned the device and released it.
  bool release(const PeerId& participant);
  void release_any();
  [[nodiscard]] bool owned_by(const PeerId& participant) const noexcept {
    return !owner_.empty() && owner_participant_ == participant;
  }
  [[nodiscard]] const std::string& owner() const noexcept { return owner_; }  // the claim's client id ("": free)
  [[nodiscard]] const PeerId& owner_participant() const noexcept { return owner_participant_; }

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

  // The owner's writers whose serials are remembered (an owner with more writers forgets the least recent).
  static constexpr std::size_t kWriters = 8;

 private:
  Verdict reject(dds::RejectReason reason);
  // The last serial accepted from `writer` (0: none yet); makes room for it if it is new.
  std::uint64_t& last_serial_of(dds_instance_handle_t writer);

  struct WriterSerial {
    dds_instance_handle_t writer = 0;
    std::uint64_t serial = 0;
    std::uint64_t used = 0;
  };

  dds::CommandBounds bounds_;
  std::int64_t max_age_ns_;
  std::string owner_;
  PeerId owner_participant_;
  std::array<WriterSerial, kWriters> serials_{};
  std::uint64_t clock_ = 0;
  std::uint64_t received_ = 0, accepted_ = 0;
  std::array<std::uint64_t, dds::kRejectReasons> rejected_{};
};

}  // namespace hapticd::server
