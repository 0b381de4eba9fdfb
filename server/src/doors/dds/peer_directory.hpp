#pragma once
// Who is on the other end of a DDS sample: the participant of the writer that wrote it, found from the sample's
// publication handle in Cyclone's discovery data - the peer the DDS door vouches for (gate/peer.hpp). A claim is
// bound to that participant (CommandGate), not to the self-declared client id in the message; and a claim ends
// when its participant is gone, which the directory tells from the writers' matching and liveliness
// (docs/safety.md, "Ownership").
//
// Bounded: at most `capacity` writers are remembered (least recently used first out), and as many writers that
// lost their liveliness. Thread-safe (the command listener, Cyclone's liveliness callbacks and the gate's service
// thread use it); never used on the loop.
#include <dds/dds.h>

#include <array>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "gate/peer.hpp"

namespace hapticd::server {

class PeerDirectory {
 public:
  explicit PeerDirectory(std::size_t capacity);

  // The participant of `writer`, a writer matched on `reader`; nullopt when it is not (or no longer) matched.
  std::optional<PeerId> participant_of(dds_entity_t reader, dds_instance_handle_t writer);
  // Whether `writer` is still matched on `reader`: a participant that exits deletes its writers, one that
  // vanishes is removed when its lease runs out.
  [[nodiscard]] bool matched(dds_entity_t reader, dds_instance_handle_t writer) const;
  // Cyclone's liveliness-changed callback of `reader` (automatic liveliness: the writer's process asserts it).
  void liveliness_changed(const dds_liveliness_changed_status_t& status);
  // Whether `participant` has a writer matched on `reader` whose liveliness has not been lost.
  [[nodiscard]] bool has_live_writer(dds_entity_t reader, const PeerId& participant);

 private:
  struct Entry {
    dds_entity_t reader = 0;
    dds_instance_handle_t writer = 0;
    PeerId participant;
    std::uint64_t used = 0;
  };
  Entry* find(dds_entity_t reader, dds_instance_handle_t writer);

  std::size_t capacity_;
  mutable std::mutex mutex_;
  std::vector<Entry> entries_;                    // at most capacity_
  std::vector<dds_instance_handle_t> not_alive_;  // writers whose liveliness was lost; at most capacity_
  std::uint64_t clock_ = 0;
};

}  // namespace hapticd::server
