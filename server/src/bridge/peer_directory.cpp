#include "bridge/peer_directory.hpp"

#include <algorithm>
#include <cstring>

namespace hapticd::server {
namespace {

// The participant of a matched writer from discovery (allocates; freed here).
std::optional<PeerId> lookup(dds_entity_t reader, dds_instance_handle_t writer) {
  dds_builtintopic_endpoint_t* data = dds_get_matched_publication_data(reader, writer);
  if (data == nullptr) return std::nullopt;
  PeerId id;
  static_assert(sizeof id.guid == sizeof data->participant_key.v);
  std::memcpy(id.guid.data(), data->participant_key.v, id.guid.size());
  dds_builtintopic_free_endpoint(data);
  return id;
}

}  // namespace

std::string PeerId::text() const {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string s;
  for (std::size_t i = 0; i < 12; ++i) {  // the prefix: host, process, participant
    s += kHex[guid[i] >> 4];
    s += kHex[guid[i] & 0xf];
  }
  return s;
}

namespace {
constexpr std::uint64_t kSocketTag = 0x5eca7e1100000000ull;  // the top 32 bits of a socket's writer handle
constexpr std::uint64_t kSocketMask = 0xffffffff00000000ull;
}  // namespace

PeerId PeerId::of_socket(std::uint64_t connection) noexcept {
  PeerId id;
  std::memcpy(id.guid.data(), "hapticdw", 8);  // 8 bytes, the connection's 4, then entity id ffffffff
  for (int b = 0; b < 4; ++b) id.guid[8 + b] = static_cast<unsigned char>(connection >> (8 * (3 - b)));
  id.guid[12] = id.guid[13] = id.guid[14] = id.guid[15] = 0xff;
  return id;
}

PeerId PeerId::of_link() noexcept {
  PeerId id;
  std::memcpy(id.guid.data(), "hapticdt", 8);  // then zeros and entity id fffffffe: no participant's, no socket's
  id.guid[12] = id.guid[13] = id.guid[14] = 0xff;
  id.guid[15] = 0xfe;
  return id;
}

bool PeerId::is_socket() const noexcept {
  return std::memcmp(guid.data(), "hapticdw", 8) == 0 && guid[12] == 0xff && guid[13] == 0xff && guid[14] == 0xff &&
         guid[15] == 0xff;
}

dds_instance_handle_t socket_writer(std::uint64_t connection) noexcept {
  return kSocketTag | (connection & ~kSocketMask);
}
bool is_socket_writer(dds_instance_handle_t writer) noexcept { return (writer & kSocketMask) == kSocketTag; }

PeerDirectory::PeerDirectory(std::size_t capacity) : capacity_(std::max<std::size_t>(capacity, 1)) {
  entries_.reserve(capacity_);
  not_alive_.reserve(capacity_);
}

PeerDirectory::Entry* PeerDirectory::find(dds_entity_t reader, dds_instance_handle_t writer) {
  for (Entry& e : entries_)
    if (e.reader == reader && e.writer == writer) return &e;
  return nullptr;
}

std::optional<PeerId> PeerDirectory::participant_of(dds_entity_t reader, dds_instance_handle_t writer) {
  {
    std::lock_guard lock(mutex_);
    if (Entry* e = find(reader, writer)) {
      e->used = ++clock_;
      return e->participant;
    }
  }
  const std::optional<PeerId> id = lookup(reader, writer);  // outside the lock: it asks Cyclone
  if (!id) return std::nullopt;
  std::lock_guard lock(mutex_);
  if (Entry* e = find(reader, writer)) return e->participant;  // another thread was first
  Entry fresh{reader, writer, *id, ++clock_};
  if (entries_.size() < capacity_) {
    entries_.push_back(fresh);
  } else {  // the least recently used writer is forgotten (it is looked up again if it writes again)
    *std::min_element(entries_.begin(), entries_.end(),
                      [](const Entry& a, const Entry& b) { return a.used < b.used; }) = fresh;
  }
  return id;
}

void PeerDirectory::socket_opened(std::uint64_t connection) {
  std::lock_guard lock(mutex_);
  sockets_.push_back(connection);
}

void PeerDirectory::socket_closed(std::uint64_t connection) {
  std::lock_guard lock(mutex_);
  sockets_.erase(std::remove(sockets_.begin(), sockets_.end(), connection), sockets_.end());
}

bool PeerDirectory::socket_open(std::uint64_t connection) const {
  std::lock_guard lock(mutex_);
  return std::find(sockets_.begin(), sockets_.end(), connection) != sockets_.end();
}

bool PeerDirectory::matched(dds_entity_t reader, dds_instance_handle_t writer) const {
  if (is_socket_writer(writer)) return socket_open(writer & ~kSocketMask);
  dds_builtintopic_endpoint_t* data = dds_get_matched_publication_data(reader, writer);
  if (data == nullptr) return false;
  dds_builtintopic_free_endpoint(data);
  return true;
}

void PeerDirectory::liveliness_changed(const dds_liveliness_changed_status_t& status) {
  const dds_instance_handle_t writer = status.last_publication_handle;
  std::lock_guard lock(mutex_);
  const auto known = std::find(not_alive_.begin(), not_alive_.end(), writer);
  if (status.not_alive_count_change > 0) {  // alive -> not alive: its process stopped asserting liveliness
    if (known != not_alive_.end()) return;
    if (not_alive_.size() >= capacity_) not_alive_.erase(not_alive_.begin());  // the oldest loss is forgotten
    not_alive_.push_back(writer);
  } else if (known != not_alive_.end()) {  // alive again, or gone (then it is no longer matched either)
    not_alive_.erase(known);
  }
}

bool PeerDirectory::has_live_writer(dds_entity_t reader, const PeerId& participant) {
  if (participant.is_socket()) {  // its connection is open: the same check as its requests'
    std::lock_guard lock(mutex_);
    return std::any_of(sockets_.begin(), sockets_.end(),
                       [&](std::uint64_t c) { return PeerId::of_socket(c) == participant; });
  }
  std::vector<dds_instance_handle_t> handles(64);
  dds_return_t n = dds_get_matched_publications(reader, handles.data(), handles.size());
  if (n > static_cast<dds_return_t>(handles.size())) {  // more writers than room: ask again with room for all
    handles.resize(static_cast<std::size_t>(n));
    n = dds_get_matched_publications(reader, handles.data(), handles.size());
  }
  if (n <= 0) return false;
  for (std::size_t i = 0; i < std::min(static_cast<std::size_t>(n), handles.size()); ++i) {
    const std::optional<PeerId> p = participant_of(reader, handles[i]);
    if (!p || !(*p == participant)) continue;
    std::lock_guard lock(mutex_);
    if (std::find(not_alive_.begin(), not_alive_.end(), handles[i]) == not_alive_.end()) return true;
  }
  return false;
}

}  // namespace hapticd::server
