#include "gate/command_gate.hpp"

#include <algorithm>

#include "hapticd/dds/conversion.hpp"

namespace hapticd::server {

bool CommandGate::may_claim(std::string_view client, const PeerId& peer) const noexcept {
  if (client.empty() || peer.empty()) return false;
  return owner_.empty() || (owner_peer_ == peer && owner_ == client);
}

bool CommandGate::claim(std::string_view client, const PeerId& peer) {
  if (!may_claim(client, peer)) return false;
  owner_ = std::string(client);
  owner_peer_ = peer;
  serials_ = {};  // a (re)claiming engine starts its serial numbers again
  return true;
}

bool CommandGate::release(const PeerId& peer) {
  if (!owned_by(peer)) return false;
  release_any();
  return true;
}

void CommandGate::release_any() {
  owner_.clear();
  owner_peer_ = PeerId{};
  serials_ = {};
}

CommandGate::Verdict CommandGate::reject(dds::RejectReason reason) {
  ++rejected_[static_cast<std::size_t>(reason)];
  return {false, reason};
}

std::uint64_t CommandGate::rejected_total() const noexcept {
  std::uint64_t n = 0;
  for (auto r : rejected_) n += r;
  return n;
}

std::uint64_t& CommandGate::last_serial_of(std::uint64_t channel) {
  ++clock_;
  for (WriterSerial& w : serials_)
    if (w.channel == channel) {
      w.used = clock_;
      return w.serial;
    }
  WriterSerial& slot = *std::min_element(serials_.begin(), serials_.end(),
                                         [](const WriterSerial& a, const WriterSerial& b) { return a.used < b.used; });
  slot = WriterSerial{channel, 0, clock_};
  return slot.serial;
}

CommandGate::Verdict CommandGate::admit(const hapticd_msg_EngineCommand& command, const Sender& sender,
                                        std::int64_t source_ns, std::int64_t now_ns) {
  ++received_;
  if (const dds::ContentCheck c = dds::check_command_content(command, bounds_); !c.ok) return reject(c.reason);
  if (!owned_by(sender.peer) || dds::text_of(command.engine) != owner_) return reject(dds::RejectReason::not_owner);
  std::uint64_t& last_serial = last_serial_of(sender.channel);
  if (command.serial <= last_serial) return reject(dds::RejectReason::out_of_order);
  // Fresh: not older than the limit, and not from the future beyond it either (a clock that is off).
  const std::int64_t age = now_ns - source_ns;
  if (age > max_age_ns_ || age < -max_age_ns_) return reject(dds::RejectReason::stale);
  last_serial = command.serial;
  ++accepted_;
  return {true, dds::RejectReason::other};
}

}  // namespace hapticd::server
