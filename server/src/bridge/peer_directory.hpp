#pragma once
// Who is on the other end of a sample: the DDS participant of the writer that wrote it, found from the sample's
// publication handle in Cyclone's discovery data. A claim is bound to that participant (CommandGate), not to the
// self-declared client id in the message; and a claim ends when its participant is gone, which the directory
// tells from the writers' matching and liveliness (docs/safety.md, "Ownership").
//
// Bounded: at most `capacity` writers are remembered (least recently used first out), and as many writers that
// lost their liveliness. Thread-safe (the command listener, Cyclone's liveliness callbacks and the bridge's
// receiver use it); never used on the loop.
#include <dds/dds.h>

#include <array>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace hapticd::server {

// A DDS participant, by its GUID (its key in discovery), or a client of the engine socket (a GUID no DDS
// participant has: its entity id is not a participant's). All zero: nobody.
struct PeerId {
  std::array<unsigned char, 16> guid{};
  friend bool operator==(const PeerId&, const PeerId&) = default;
  [[nodiscard]] bool empty() const noexcept { return *this == PeerId{}; }
  // The GUID's prefix as hex (for messages: "participant 0110a4c3...").
  [[nodiscard]] std::string text() const;
  // The engine socket's client `connection` (and whether a peer is one).
  static PeerId of_socket(std::uint64_t connection) noexcept;
  [[nodiscard]] bool is_socket() const noexcept;
  // The server's own teleoperation link (bridge/teleop_link): it holds its device's claim for the session.
  static PeerId of_link() noexcept;
  [[nodiscard]] bool is_link() const noexcept { return *this == of_link(); }
};

// The writer handle that stands for an engine socket's client (its requests and commands), and whether a writer
// handle is one. Cyclone's handles are 64-bit random-looking numbers: one with these 32 top bits is not
// expected (2^-32 per writer).
[[nodiscard]] dds_instance_handle_t socket_writer(std::uint64_t connection) noexcept;
[[nodiscard]] bool is_socket_writer(dds_instance_handle_t writer) noexcept;

class PeerDirectory {
 public:
  explicit PeerDirectory(std::size_t capacity);

  // The participant of `writer`, a writer matched on `reader`; nullopt when it is not (or no longer) matched.
  std::optional<PeerId> participant_of(dds_entity_t reader, dds_instance_handle_t writer);
  // Whether `writer` is still matched on `reader`: a participant that exits deletes its writers, one that
  // vanishes is removed when its lease runs out. An engine socket's client: while its connection is open.
  [[nodiscard]] bool matched(dds_entity_t reader, dds_instance_handle_t writer) const;
  // Cyclone's liveliness-changed callback of `reader` (automatic liveliness: the writer's process asserts it).
  void liveliness_changed(const dds_liveliness_changed_status_t& status);
  // Whether `participant` has a writer matched on `reader` whose liveliness has not been lost (an engine socket's
  // client: while its connection is open; the socket's pings close a frozen one).
  [[nodiscard]] bool has_live_writer(dds_entity_t reader, const PeerId& participant);
  // The engine socket's connections (its thread): open from the handshake until closed.
  void socket_opened(std::uint64_t connection);
  void socket_closed(std::uint64_t connection);
  [[nodiscard]] bool socket_open(std::uint64_t connection) const;

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
  std::vector<std::uint64_t> sockets_;            // the engine socket's open connections (at most its clients)
  std::uint64_t clock_ = 0;
};

}  // namespace hapticd::server
