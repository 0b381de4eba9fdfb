#include "doors/dds/peer_directory.hpp"

#include <algorithm>
#include <cstring>

namespace hapticd::server {
namespace {

// The participant of a matched writer from discovery (allocates; freed here).
std::optional<PeerId> lookup(dds_entity_t reader, dds_instance_handle_t writer) {
  dds_builtintopic_endpoint_t* data = dds_get_matched_publication_data(reader, writer);
  if (data == nullptr) return std::nullopt;
  std::array<unsigned char, 16> guid{};
  static_assert(sizeof guid == sizeof data->participant_key.v);
  std::memcpy(guid.data(), data->participant_key.v, guid.size());
  dds_builtintopic_free_endpoint(data);
  return PeerId::dds_participant(guid);
}

}  // namespace

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

bool PeerDirectory::matched(dds_entity_t reader, dds_instance_handle_t writer) const {
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
  if (participant.door != DoorKind::dds) return false;
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
