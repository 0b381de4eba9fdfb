#include "gate/request_dispatcher.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>

#include "executor/loop_clock.hpp"
#include "hapticd/dds/conversion.hpp"
#include "hapticd/demand.hpp"
#include "session/device_requests.hpp"

namespace hapticd::server {

RequestDispatcher::RequestDispatcher(DeviceGates& devices, EventFanout& events, StateFanout& publisher,
                                     double claim_grace_s, double claim_hold_s, bool tuning_by_anyone)
    : devices_(devices),
      events_(events),
      publisher_(publisher),
      claim_grace_ns_(static_cast<std::int64_t>(claim_grace_s * 1e9)),
      claim_hold_ns_(static_cast<std::int64_t>(claim_hold_s * 1e9)),
      tuning_by_anyone_(tuning_by_anyone) {}

namespace {

bool is_group_request(hapticd_msg_RequestKind kind) noexcept {
  return kind == hapticd_msg_REQUEST_GROUP_CLAIM || kind == hapticd_msg_REQUEST_GROUP_RELEASE ||
         kind == hapticd_msg_REQUEST_GROUP_ESTOP || kind == hapticd_msg_REQUEST_GROUP_RECOVER;
}

}  // namespace

void RequestDispatcher::set_doors(const std::vector<Door*>& doors) {
  for (Door* d : doors) doors_[static_cast<std::size_t>(d->kind())] = d;
}

hapticd_msg_ControlReply RequestDispatcher::answer(const hapticd_msg_ControlRequest& m,
                                                   const std::optional<Sender>& sender) {
  const std::optional<PeerId> requester = sender ? std::optional<PeerId>(sender->peer) : std::nullopt;
  const std::string target(dds::text_of(m.device));
  DeviceGate* d = devices_.find(target);
  GroupGate* g = devices_.find_group(target);
  const bool every = target == "*";
  std::vector<DeviceGate*> members;  // a group request's devices
  if (g != nullptr)
    for (std::size_t i : g->members) members.push_back(&devices_[i]);
  if (every)
    for (auto& link : devices_) members.push_back(link.get());
  if (d != nullptr) d->requests.fetch_add(1, std::memory_order_relaxed);
  for (DeviceGate* member : members) member->requests.fetch_add(1, std::memory_order_relaxed);
  if (requester) {
    if (const hapticd_msg_ControlReply* again = answered_->find(*requester, m))
      return *again;  // sent again: the same answer, nothing applied twice
  }
  Answer answer;
  bool dispatched = false;
  if (d == nullptr && g == nullptr && !every) {
    answer.message = "'" + target + "' is neither a device nor a group of this server";
  } else if (dds::text_of(m.client).empty() || !dds::terminated(m.client) || !dds::terminated(m.subject)) {
    answer.message = "malformed request (no client id)";
  } else if (!dds::valid_text(m.client) || !dds::valid_text(m.subject)) {
    // Its id would reach the engine socket's and the live view's JSON clients (owner, "stopped by ..."): refused.
    const std::uint64_t n = text_refused_.fetch_add(1, std::memory_order_relaxed) + 1;
    if (n == 1 || n % 100 == 0)
      spdlog::warn("a request whose client id or subject is not UTF-8 was refused ({} so far)", n);
    answer.message = "malformed request (the client id or subject is not UTF-8 text)";
  } else if (!requester) {
    answer.message = "request from a sender that is no longer known";
  } else {
    dispatched = true;
    const Request r{
        m,
        *sender,
        *requester,
        dds::text_of(m.client),
        dds::text_of(m.subject),
        std::vector<double>(m.values, m.values + std::clamp<std::int32_t>(m.value_count, 0, hapticd_msg_MAX_VALUES))};
    try {  // whatever a request meets (a plugin that throws, memory) is its refusal, never the thread's end
      if (is_group_request(m.kind)) {
        answer = d != nullptr ? Answer{false, "'" + target + "' is a device: group requests name a group"}
                              : dispatch_group(members, every, r);
      } else {
        answer = d != nullptr ? dispatch(*d, r) : Answer{false, "'" + target + "' is not a device: name one"};
      }
    } catch (const std::exception& e) {
      answer = Answer{false, std::string("the request failed: ") + e.what()};
    } catch (...) {
      answer = Answer{false, "the request failed"};
    }
  }
  hapticd_msg_ControlReply reply{};
  dds::set_text(reply.device, target);
  dds::set_text(reply.client, dds::text_of(m.client));
  reply.request_id = m.request_id;
  reply.accepted = answer.accepted;
  dds::set_text(reply.message, answer.message);
  const std::size_t count = std::min<std::size_t>(answer.values.size(), hapticd_msg_MAX_VALUES);
  reply.value_count = static_cast<std::int32_t>(count);
  std::copy_n(answer.values.begin(), count, reply.values);
  if (dispatched) answered_->remember(*requester, reply);
  return reply;
}

RequestDispatcher::Answer RequestDispatcher::dispatch_group(const std::vector<DeviceGate*>& members, bool every,
                                                            const Request& r) {
  switch (r.message.kind) {
    case hapticd_msg_REQUEST_GROUP_CLAIM:
      if (every) return {false, "claim a group by its name (\"*\" is for E-stop and recovery)"};
      return group_claim(members, r);
    case hapticd_msg_REQUEST_GROUP_RELEASE:
      if (every) return {false, "release a group by its name (\"*\" is for E-stop and recovery)"};
      return group_release(members, r);
    case hapticd_msg_REQUEST_GROUP_ESTOP:
      return group_stop(members, r);
    case hapticd_msg_REQUEST_GROUP_RECOVER:
      return group_recover(members, r);
    default:
      return {false, "not a group request"};
  }
}

namespace {

std::string names_of(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

}  // namespace

RequestDispatcher::Answer RequestDispatcher::group_claim(const std::vector<DeviceGate*>& members, const Request& r) {
  // All or none. Every request is answered on this one thread, one at a time, and only requests and the claim
  // check (also this thread) change ownership: nothing can claim a device between the check and the claims.
  // The check is the gate's own rule (free, or this participant's under this client id), so a device claimed
  // under another client id of the same participant is refused here, not half-way through the claims.
  std::vector<std::string> taken, claimed;
  for (const DeviceGate* d : members) {
    std::lock_guard lock(d->mutex);
    if (!d->gate.may_claim(r.client, r.requester)) taken.push_back(d->device->name() + " by '" + d->gate.owner() + "'");
  }
  if (!taken.empty()) return {false, "none claimed: " + names_of(taken) + " claimed already"};
  for (DeviceGate* d : members) {
    const Answer a = claim(*d, r);
    if (!a.accepted) {  // cannot happen after the check above; if it ever does, undo the claims: all or none
      for (DeviceGate* c : members)
        if (std::find(claimed.begin(), claimed.end(), c->device->name()) != claimed.end()) (void)release(*c, r);
      return {false, "none claimed: " + d->device->name() + ": " + a.message};
    }
    claimed.push_back(d->device->name());
  }
  return {true, "claimed " + names_of(claimed)};
}

RequestDispatcher::Answer RequestDispatcher::group_release(const std::vector<DeviceGate*>& members, const Request& r) {
  std::vector<std::string> released;
  for (DeviceGate* d : members)
    if (release(*d, r).accepted) released.push_back(d->device->name());
  if (released.empty()) return {false, "not the owner of any of its devices"};
  return {true, "released " + names_of(released)};
}

RequestDispatcher::Answer RequestDispatcher::group_stop(const std::vector<DeviceGate*>& members, const Request& r) {
  std::vector<std::string> stopped;  // anyone may stop a device
  for (DeviceGate* d : members)
    if (emergency_stop(*d, r).accepted) stopped.push_back(d->device->name());
  if (stopped.size() != members.size()) return {false, "stopped only " + names_of(stopped)};
  return {true, "stopped " + names_of(stopped)};
}

RequestDispatcher::Answer RequestDispatcher::group_recover(const std::vector<DeviceGate*>& members, const Request& r) {
  // The requester's own stops of these devices are released (lockout-tagout: nobody else can); the recovery is
  // all or none: every device must be the requester's to recover and in its safe mode.
  std::vector<std::string> refusals, recovered;
  for (DeviceGate* d : members) {
    if (auto refused = refused_recovery(*d, r))
      refusals.push_back(d->device->name() + " " + refused->message);
    else if (d->device->status().fault() == DeviceFault::none)
      refusals.push_back(d->device->name() + " is not in its safe mode");
  }
  if (!refusals.empty()) return {false, "none recovered: " + names_of(refusals)};
  for (DeviceGate* d : members) {
    const Answer a = forward(*d, DeviceRequest::Kind::recover, r);
    if (!a.accepted) return {false, "recovered " + names_of(recovered) + "; " + d->device->name() + ": " + a.message};
    recovered.push_back(d->device->name());
  }
  return {true, "recovering " + names_of(recovered)};
}

RequestDispatcher::Answer RequestDispatcher::dispatch(DeviceGate& d, const Request& r) {
  switch (r.message.kind) {
    case hapticd_msg_REQUEST_CLAIM:
      return claim(d, r);
    case hapticd_msg_REQUEST_RELEASE:
      return release(d, r);
    case hapticd_msg_REQUEST_SWITCH_SCHEME:
      return switch_scheme(d, r);
    case hapticd_msg_REQUEST_SET_PARAMETER:
      return set_parameter(d, r);
    case hapticd_msg_REQUEST_GET_PARAMETER:
      return get_parameter(d, r);
    case hapticd_msg_REQUEST_DESCRIBE_PARAMETER:
      return forward(d, DeviceRequest::Kind::describe_parameter, r);  // reading: anyone may
    case hapticd_msg_REQUEST_OPERATOR:
      return drive_operator(d, r);
    case hapticd_msg_REQUEST_ESTOP:
      return emergency_stop(d, r);
    case hapticd_msg_REQUEST_RECOVER:
      return recover(d, r);
    case hapticd_msg_REQUEST_DESCRIBE:
      return describe(d, r);
    default:
      return {false, "unknown request kind"};
  }
}

std::optional<RequestDispatcher::Answer> RequestDispatcher::refused_unless_owner(const DeviceGate& d,
                                                                                 const Request& r) const {
  std::lock_guard lock(d.mutex);
  if (d.gate.owner().empty() || d.gate.owned_by(r.requester)) return std::nullopt;
  return Answer{false, "claimed by '" + d.gate.owner() + "'"};
}

RequestDispatcher::Answer RequestDispatcher::claim(DeviceGate& d, const Request& r) {
  Answer a;
  {
    std::lock_guard lock(d.mutex);
    a.accepted = d.gate.claim(r.client, r.requester);
    if (a.accepted) {
      d.claim_channel = r.sender;
      d.claimed_ns = monotonic_now_ns();
    }
    a.message = a.accepted ? "claimed" : "claimed by '" + d.gate.owner() + "' (another participant)";
  }
  if (a.accepted) events_.send(d, hapticd_msg_EVENT_OWNER, r.client, std::string(r.client) + " claimed the device");
  return a;
}

RequestDispatcher::Answer RequestDispatcher::release(DeviceGate& d, const Request& r) {
  bool released = false;
  {
    std::lock_guard lock(d.mutex);
    released = d.gate.release(r.requester);
  }
  if (!released) return {false, "not the owner"};
  d.device->end_engine_input();  // a clean release: the forces fade, the engine is not stale
  d.synced.store(false, std::memory_order_release);
  events_.send(d, hapticd_msg_EVENT_OWNER, "", std::string(r.client) + " released the device");
  return {true, "released"};
}

RequestDispatcher::Answer RequestDispatcher::forward(DeviceGate& d, DeviceRequest::Kind kind, const Request& r) {
  RuntimeReply rr = d.device->apply(DeviceRequest{kind, std::string(r.name), r.values});
  return {rr.accepted, std::move(rr.message), std::move(rr.values)};
}

RequestDispatcher::Answer RequestDispatcher::switch_scheme(DeviceGate& d, const Request& r) {
  if (auto refused = refused_unless_owner(d, r)) return *refused;
  return forward(d, DeviceRequest::Kind::switch_scheme, r);
}

RequestDispatcher::Answer RequestDispatcher::set_parameter(DeviceGate& d, const Request& r) {
  // A claimed device's owner sets its parameters; with gate.tuning_by anyone, others may set its tunable ones too
  // (the owner hears of it below), never its safety settings.
  if (auto refused = refused_unless_owner(d, r); refused && (!tuning_by_anyone_ || r.name.rfind("safety.", 0) == 0))
    return *refused;
  Answer a = forward(d, DeviceRequest::Kind::set_parameter, r);
  if (a.accepted) {  // every client hears of it: an engine whose model mirrors the parameter re-reads it
    std::string values;
    for (double v : r.values) values += (values.empty() ? "" : ", ") + fmt::format("{:g}", v);
    const std::string_view slot = r.name.substr(0, r.name.find('.'));
    events_.send(
        d, hapticd_msg_EVENT_PARAMETER, slot,
        fmt::format("{} = {} (set by '{}')", r.name, r.values.size() == 1 ? values : "[" + values + "]", r.client));
  }
  return a;
}

RequestDispatcher::Answer RequestDispatcher::get_parameter(DeviceGate& d, const Request& r) {
  return forward(d, DeviceRequest::Kind::get_parameter, r);  // reading changes nothing: anyone may
}

RequestDispatcher::Answer RequestDispatcher::drive_operator(DeviceGate& d, const Request& r) {
  // The simulated operator is the person at the device, not the device: anyone may drive it.
  return forward(d, DeviceRequest::Kind::drive_operator, r);
}

RequestDispatcher::Answer RequestDispatcher::emergency_stop(DeviceGate& d, const Request& r) {
  {  // anyone may stop a device; the stop holds until its requester releases it
    std::lock_guard lock(d.mutex);
    d.stops.add(Stopper{r.sender, std::string(r.client)});
  }
  return forward(d, DeviceRequest::Kind::emergency_stop, r);
}

bool RequestDispatcher::gone(const Sender& s) const {
  const Door* door = doors_[static_cast<std::size_t>(s.peer.door)];
  return door == nullptr || !door->channel_open(s);
}

bool RequestDispatcher::alive(const PeerId& p) const {
  Door* door = doors_[static_cast<std::size_t>(p.door)];
  return door != nullptr && door->alive(p);
}

std::optional<RequestDispatcher::Answer> RequestDispatcher::refused_recovery(DeviceGate& d, const Request& r) {
  std::lock_guard lock(d.mutex);
  const bool stopper = d.stops.release(r.requester, r.client, [this](const Sender& s) { return gone(s); });
  if (!d.stops.empty())
    return Answer{false, std::string(stopper ? "its stop released, " : "") + "stopped by " + d.stops.holders() +
                             ": only who stopped it can release its stop"};
  // A device its server's teleoperation link or ROS 2 holds for the session is recovered by whoever asks (the link
  // cannot ask; the person at the device does): as a free device's, its E-stops requested through a door still
  // latch under their stoppers.
  if (stopper || d.gate.owner().empty() || d.gate.owner_peer().holds_for_session() || d.gate.owned_by(r.requester))
    return std::nullopt;
  return Answer{false, "claimed by '" + d.gate.owner() + "'"};
}

RequestDispatcher::Answer RequestDispatcher::recover(DeviceGate& d, const Request& r) {
  if (auto refused = refused_recovery(d, r)) return *refused;
  return forward(d, DeviceRequest::Kind::recover, r);
}

RequestDispatcher::Answer RequestDispatcher::describe(DeviceGate& d, const Request&) {
  publisher_.publish_description(d.index);
  return {true, "description republished"};
}

void RequestDispatcher::check_claims() {
  const std::int64_t now = monotonic_now_ns();
  for (auto& link : devices_) {
    DeviceGate& d = *link;
    PeerId owner;
    Sender claim_channel;
    std::int64_t claimed_ns = 0;
    {
      std::lock_guard lock(d.mutex);
      if (d.gate.owner().empty() || d.gate.owner_peer().holds_for_session()) continue;  // the session's claim
      owner = d.gate.owner_peer();
      claim_channel = d.claim_channel;
      claimed_ns = d.claimed_ns;
    }
    const char* why = nullptr;
    if (gone(claim_channel)) {
      why = owner.is_socket() ? "closed its connection" : "left the domain";
    } else if (now - claimed_ns > claim_grace_ns_ && !alive(owner)) {
      if (d.silent_since_ns == 0 || d.silent_claimed_ns != claimed_ns) {
        d.silent_since_ns = now;  // the hold starts
        d.silent_claimed_ns = claimed_ns;
      }
      if (now - d.silent_since_ns > claim_hold_ns_)
        why = "has had no live command writer for the claim's hold (its process died, froze or never had one)";
    } else {
      d.silent_since_ns = 0;  // alive again (or still within the grace): the hold starts anew next time
    }
    if (why == nullptr) continue;
    std::string lost;
    {
      std::lock_guard lock(d.mutex);
      if (!d.gate.owned_by(owner) || d.claimed_ns != claimed_ns) continue;  // released or claimed anew meanwhile
      lost = d.gate.owner();
      d.gate.release_any();
    }
    d.synced.store(false, std::memory_order_release);
    claims_ended_.fetch_add(1, std::memory_order_relaxed);
    events_.send(d, hapticd_msg_EVENT_OWNER, "", "engine '" + lost + "' " + why + ": the device is free again");
  }
}

}  // namespace hapticd::server
