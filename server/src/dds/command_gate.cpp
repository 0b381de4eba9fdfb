#include "dds/command_gate.hpp"

#include "hapticd/dds/conversion.hpp"

namespace hapticd::server {

bool CommandGate::claim(std::string_view client) {
  if (client.empty()) return false;
  if (!owner_.empty() && owner_ != client) return false;
  owner_ = std::string(client);
  last_serial_ = 0;  // a (re)claiming engine starts its serial numbers again
  return true;
}

bool CommandGate::release(std::string_view client) {
  if (owner_.empty() || owner_ != client) return false;
  owner_.clear();
  return true;
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

CommandGate::Verdict CommandGate::admit(const hapticd_msg_EngineCommand& command, std::int64_t source_ns, std::int64_t now_ns) {
  ++received_;
  if (const dds::ContentCheck c = dds::check_command_content(command, bounds_); !c.ok) return reject(c.reason);
  if (owner_.empty() || dds::text_of(command.engine) != owner_) return reject(dds::RejectReason::not_owner);
  if (command.serial <= last_serial_) return reject(dds::RejectReason::out_of_order);
  // Fresh: not older than the limit, and not from the future beyond it either (a clock that is off).
  const std::int64_t age = now_ns - source_ns;
  if (age > max_age_ns_ || age < -max_age_ns_) return reject(dds::RejectReason::stale);
  last_serial_ = command.serial;
  ++accepted_;
  return {true, dds::RejectReason::other};
}

}  // namespace hapticd::server
