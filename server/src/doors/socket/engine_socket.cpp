#include "doors/socket/engine_socket.hpp"

#include <sched.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "doors/socket/socket_pages.hpp"
#include "executor/loop_clock.hpp"
#include "gate/request_dispatcher.hpp"
#include "hapticd/dds/conversion.hpp"
#include "session/device_requests.hpp"

namespace hapticd::server {

using net::ConnectionId;
using net::WebSocketServer;

namespace {

socket_messages::InventoryDevice inventory_of(const DeviceGate& d) {
  const DeviceRequests& device = *d.device;
  const DeviceDescription& description = device.description();
  socket_messages::InventoryDevice out;
  out.name = device.name();
  out.model = description.model;
  out.interface = description.interface == DeviceInterface::handle ? "handle" : "joints";
  out.dof = description.dof();
  out.simulated = description.simulated;
  out.command_deadline_s = device.chain().engine_deadline_s;
  for (int i = 0; i < 3; ++i) out.base_position[static_cast<std::size_t>(i)] = description.base_pose.position[i];
  const Eigen::Quaterniond& q = description.base_pose.orientation;
  out.base_orientation = {q.w(), q.x(), q.y(), q.z()};
  for (const SchemeChain& s : device.chain().schemes) out.schemes.push_back(s.name);
  out.scheme = device.schemes().active_name();
  return out;
}

// A gate's reason as an error code (the enumerator's name).
std::string_view code_of(dds::RejectReason reason) {
  switch (reason) {
    case dds::RejectReason::malformed:
      return "malformed";
    case dds::RejectReason::non_finite:
      return "non_finite";
    case dds::RejectReason::out_of_bounds:
      return "out_of_bounds";
    case dds::RejectReason::out_of_order:
      return "out_of_order";
    case dds::RejectReason::stale:
      return "stale";
    case dds::RejectReason::not_owner:
      return "not_owner";
    case dds::RejectReason::wrong_kind:
      return "wrong_kind";
    default:
      return "rejected";
  }
}

}  // namespace

EngineSocket::EngineSocket(const EngineSocketSettings& settings, Gate& gate, std::vector<int> cpus)
    : settings_(settings),
      gate_(gate),
      devices_(gate.devices()),
      session_id_(static_cast<std::uint64_t>(std::chrono::system_clock::now().time_since_epoch().count())),
      wanted_(std::make_unique<std::atomic<bool>[]>(devices_.size())) {
  for (const auto& d : devices_) inventory_.push_back(inventory_of(*d));
  for (const GroupGate& g : devices_.groups()) {
    socket_messages::InventoryGroup group{g.name, {}};
    for (std::size_t i : g.members) group.devices.push_back(devices_[i].device->name());
    groups_.push_back(std::move(group));
  }
  net::WebSocketOptions o;
  o.what = "engine socket";
  o.address = settings.address;
  o.port = settings.port;
  o.max_clients = settings.max_clients;
  o.server_header = "hapticd engine socket";
  o.subprotocol_hint =
      "hapticd's engine socket speaks WebSocket: connect with a WebSocket client (docs/engine-socket.md)";
  o.token = settings.token;
  o.tls_certificate_file = settings.tls_certificate_file.string();
  o.tls_private_key_file = settings.tls_private_key_file.string();
  // A state is worth nothing once the next one is out: about 100 states of one device wait at most, and a
  // client that takes nothing for a second is cut off (its claim ends, its device's forces fade).
  o.max_queued_bytes = 96u << 10;
  o.max_queued_replies = 2 * kRequestsPerClient;
  o.max_message_bytes = 16u << 10;
  o.slow_timeout = std::chrono::milliseconds(1000);
  o.keepalive_timeout = std::chrono::milliseconds(1000);
  o.send_buffer_bytes = 64u << 10;  // states wait here, counted, not in the kernel's megabytes
  o.idle_timeout = std::chrono::milliseconds(10000);
  o.allowed_origins = settings.allowed_origins;
  o.cpus = std::move(cpus);
  o.origin_hint = "the origins listed in the session's engine_socket.allowed_origins";
  // A wall engine and the haptic scene in the browser, from the socket's own origin ("/" is the wall's).
  o.pages = {{"/wall.html", wall_page()}, {"/scene.html", scene_page()}};
  server_ = std::make_unique<WebSocketServer>(std::move(o), *this);
}

EngineSocket::~EngineSocket() { stop(); }

void EngineSocket::start() { server_->start(); }

void EngineSocket::stop() {
  server_->stop();
  // Every connection is gone: their claims end at the service thread's next check.
  {
    std::lock_guard lock(open_mutex_);
    open_.clear();
  }
  clients_.clear();
  count_subscribers();
}

std::string EngineSocket::url() const {
  const bool v6 = settings_.address.find(':') != std::string::npos;
  return (settings_.tls_certificate_file.empty() ? "ws://" : "wss://") +
         (v6 ? "[" + settings_.address + "]" : settings_.address) + ":" + std::to_string(server_->port());
}

void EngineSocket::opened(ConnectionId id) {
  Client& c = clients_[id];
  c.id = "socket-" + std::to_string(id);
  c.subscribed.assign(devices_.size(), true);  // every device's states, as Haply's service sends them
  c.allowance = std::max(10.0, settings_.max_messages_per_s / 10.0);
  c.refilled_ns = monotonic_now_ns();
  {
    std::lock_guard lock(open_mutex_);
    open_.push_back(id);
  }
  count_subscribers();
  server_->send(id,
                std::make_shared<const std::string>(socket_messages::inventory(session_id_, c.id, inventory_, groups_)),
                false, WebSocketServer::Kind::reply);
}

void EngineSocket::closed(ConnectionId id) {
  clients_.erase(id);
  {
    std::lock_guard lock(open_mutex_);
    open_.erase(std::remove(open_.begin(), open_.end(), id), open_.end());
  }
  count_subscribers();
  gate_.wake();  // its claims end now, not at the next periodic check
}

bool EngineSocket::idle(ConnectionId id) const {
  const auto it = clients_.find(id);
  return it == clients_.end() ||
         std::none_of(it->second.subscribed.begin(), it->second.subscribed.end(), [](bool s) { return s; });
}

bool EngineSocket::allowed(Client& c, std::int64_t now_ns) {
  const double burst = std::max(10.0, settings_.max_messages_per_s / 10.0);
  c.allowance =
      std::min(burst, c.allowance + static_cast<double>(now_ns - c.refilled_ns) * 1e-9 * settings_.max_messages_per_s);
  c.refilled_ns = now_ns;
  if (c.allowance < 1.0) return false;
  c.allowance -= 1.0;
  return true;
}

void EngineSocket::tell(ConnectionId id, std::uint64_t count, std::string_view code, const std::string& message) {
  if (count % 100 != 1) return;  // the first, then every 100th
  server_->send(id, std::make_shared<const std::string>(socket_messages::error(code, message, count)), false,
                WebSocketServer::Kind::data);
}

void EngineSocket::received(ConnectionId id, std::string_view text, bool binary) {
  const auto it = clients_.find(id);
  if (it == clients_.end()) return;
  Client& c = it->second;
  counters_.messages.fetch_add(1, std::memory_order_relaxed);
  if (!allowed(c, monotonic_now_ns())) {
    counters_.rate_limited.fetch_add(1, std::memory_order_relaxed);
    return tell(id, ++c.limited, "rate_limited",
                "more than " + std::to_string(static_cast<long long>(settings_.max_messages_per_s)) +
                    " messages a second: the rest are dropped");
  }
  if (binary || !parser_.parse(text, c.id, c.serial, message_)) {
    counters_.malformed.fetch_add(1, std::memory_order_relaxed);
    server_->count_bad_request();
    return tell(id, ++c.malformed, "malformed",
                binary ? std::string("binary messages are not taken: send JSON text") : message_.error);
  }
  if (message_.profile) c.id = *message_.profile;
  if (message_.subscribe) subscribe(c, *message_.subscribe, id);
  for (const hapticd_msg_EngineCommand& command : message_.commands) {
    counters_.commands.fetch_add(1, std::memory_order_relaxed);
    // The connection is the peer and the channel; its commands carry no stamp of their own: received now.
    const CommandGate::Verdict v = gate_.admit(command, Sender{PeerId::socket(id), 0}, dds::wall_clock_ns());
    if (v.accepted) continue;
    counters_.rejected.fetch_add(1, std::memory_order_relaxed);
    tell(id, ++c.rejections[static_cast<std::size_t>(v.reason)], code_of(v.reason),
         "command for '" + std::string(dds::text_of(command.device)) +
             "' rejected: " + std::string(dds::to_string(v.reason)) +
             (v.reason == dds::RejectReason::not_owner ? " (claim the device first, as client '" + c.id + "')" : ""));
  }
  if (message_.scene) edit_scene(id, c);
  if (message_.request) {
    bool queued = false;
    if (c.waiting < kRequestsPerClient) {
      std::lock_guard lock(waiting_mutex_);
      if (waiting_.size() < kRequests) {
        waiting_.push_back({id, *message_.request});
        queued = true;
      }
    }
    if (!queued) {
      counters_.busy.fetch_add(1, std::memory_order_relaxed);
      hapticd_msg_ControlReply busy{};
      dds::set_text(busy.device, dds::text_of(message_.request->device));
      dds::set_text(busy.message, "too many requests waiting: wait for the answers");
      server_->send(id,
                    std::make_shared<const std::string>(
                        socket_messages::reply(static_cast<std::int64_t>(message_.request->request_id), busy)),
                    false, WebSocketServer::Kind::reply);
      return;
    }
    ++c.waiting;
    gate_.wake();
  }
}

void EngineSocket::edit_scene(ConnectionId id, Client& c) {
  // On this thread, off the loop: the object is parsed and built here, the devices take the new scene whole.
  counters_.scene_edits.fetch_add(1, std::memory_order_relaxed);
  SceneGate* scene = gate_.scene();
  const socket_messages::SceneMessage& m = *message_.scene;
  const SceneGate::Reply reply =
      scene != nullptr
          ? scene->apply(m.edit, Sender{PeerId::socket(id), 0}, c.id, monotonic_now_ns())
          : SceneGate::Reply{false, "this session has no haptic scene (its session file has no `scene` section)"};
  // A move that went through is not answered (an engine sends one per object per frame); anything else is.
  if (reply.accepted && m.edit.op == SceneGate::Op::move) return;
  server_->send(id, std::make_shared<const std::string>(socket_messages::scene_reply(m.id, reply)), false,
                WebSocketServer::Kind::reply);
}

void EngineSocket::subscribe(Client& c, const std::vector<std::string>& devices, ConnectionId id) {
  std::vector<bool> wanted(devices_.size(), false);
  for (const std::string& name : devices) {
    const DeviceGate* d = devices_.find(name);
    if (d == nullptr) return tell(id, ++c.malformed, "malformed", "subscribe: no device '" + net::quoted(name) + "'");
    wanted[d->index] = true;
  }
  c.subscribed = std::move(wanted);
  count_subscribers();
}

void EngineSocket::count_subscribers() {
  for (std::size_t i = 0; i < devices_.size(); ++i)
    wanted_[i].store(
        std::any_of(clients_.begin(), clients_.end(), [&](const auto& c) { return c.second.subscribed[i]; }),
        std::memory_order_relaxed);
}

bool EngineSocket::open(std::uint64_t connection) const {
  std::lock_guard lock(open_mutex_);
  return std::find(open_.begin(), open_.end(), connection) != open_.end();
}

bool EngineSocket::channel_open(const Sender& s) const { return s.peer.is_socket() && open(s.peer.connection()); }

bool EngineSocket::alive(const PeerId& p) { return p.is_socket() && open(p.connection()); }

void EngineSocket::state(std::size_t device, const DeviceSnapshot&, const hapticd_msg_DeviceState& s) {
  if (!wanted_[device].load(std::memory_order_relaxed)) return;
  socket_messages::state(s, state_text_);
  auto text = std::make_shared<const std::string>(state_text_);
  const bool posted = server_->post([this, device, text = std::move(text)] {
    for (const auto& [id, c] : clients_)
      if (c.subscribed[device]) {
        server_->send(id, text, false, WebSocketServer::Kind::data);
        counters_.states.fetch_add(1, std::memory_order_relaxed);
      }
  });
  // The socket thread shares the DDS threads' CPUs with this one: let it send the state now, not after the rest of
  // this thread's cycle (the DDS write, the events): the hand-off took 101 us at p90 on a 2-core machine, 12 with
  // this (docs/measurements.md, "C, C# and WebSocket engines' round trips"). Alone on a CPU it returns at once.
  if (posted) (void)sched_yield();
}

void EngineSocket::event(const hapticd_msg_Event& e) {
  const DeviceGate* d = devices_.find(dds::text_of(e.device));
  if (d == nullptr || !wanted_[d->index].load(std::memory_order_relaxed)) return;
  auto text = std::make_shared<const std::string>(socket_messages::event(e));
  (void)server_->post([this, device = d->index, text = std::move(text)] {
    for (const auto& [id, c] : clients_)
      if (c.subscribed[device]) server_->send(id, text, false, WebSocketServer::Kind::data);  // as a state
  });
}

void EngineSocket::answer_requests(RequestDispatcher& dispatcher) {
  std::deque<Waiting> batch;
  {
    std::lock_guard lock(waiting_mutex_);
    batch.swap(waiting_);
  }
  for (const Waiting& w : batch) {
    // A client that left before its turn gets nothing done (a claim for it would only end again).
    const std::optional<Sender> sender =
        open(w.connection) ? std::optional<Sender>(Sender{PeerId::socket(w.connection), 0}) : std::nullopt;
    const hapticd_msg_ControlReply reply = dispatcher.answer(w.request, sender);
    counters_.requests.fetch_add(1, std::memory_order_relaxed);
    auto text = std::make_shared<const std::string>(
        socket_messages::reply(static_cast<std::int64_t>(w.request.request_id), reply));
    const ConnectionId id = w.connection;
    (void)server_->post([this, id, text = std::move(text)] {
      const auto it = clients_.find(id);
      if (it == clients_.end()) return;
      --it->second.waiting;
      server_->send(id, text, false, WebSocketServer::Kind::reply);
    });
  }
}

}  // namespace hapticd::server
