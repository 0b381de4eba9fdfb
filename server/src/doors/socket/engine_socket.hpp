#pragma once
// The engine socket (docs/engine-socket.md): the gate's WebSocket/JSON door for clients without DDS (browsers,
// standalone headsets, engines with a WebSocket library). Each connection is a peer of its own (PeerId::socket):
// its claims are bound to the connection and end when it closes, its commands pass the gate like any door's
// (Gate::admit: owner, order, freshness, bounds; then the loop's deadline and fade), its requests are answered by
// the gate's RequestDispatcher on the gate's service thread. Threads:
//   socket thread     the transport (net/websocket_server): parses each message; commands to Gate::admit
//                     (lock-free hand-over to the loop), requests into a bounded queue for the service thread;
//   publisher thread  state(): a device's new state as JSON, handed to the socket thread for its subscribers;
//   service thread    answer_requests(): the queued requests through the dispatcher, the replies handed back.
// Bounded everywhere: clients (max_clients), messages per client and second (max_messages_per_s; more dropped,
// counted, the client told), requests waiting (per client and in all), what is queued for a client (states
// dropped when it lags; a client that takes nothing for a second is disconnected; a frozen one by the pings).
#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include "config/session_config.hpp"
#include "doors/socket/socket_messages.hpp"
#include "gate/door.hpp"
#include "gate/gate.hpp"
#include "net/websocket_server.hpp"

namespace hapticd::server {

struct EngineSocketCounters {
  std::atomic<std::uint64_t> messages{0};      // messages taken from clients
  std::atomic<std::uint64_t> malformed{0};     // messages refused as malformed (nothing of them applied)
  std::atomic<std::uint64_t> rate_limited{0};  // messages dropped by the rate limit
  std::atomic<std::uint64_t> commands{0};      // commands handed to the gate
  std::atomic<std::uint64_t> rejected{0};      // ... that it rejected
  std::atomic<std::uint64_t> requests{0};      // requests answered
  std::atomic<std::uint64_t> busy{0};          // requests refused because too many were waiting
  std::atomic<std::uint64_t> states{0};        // states sent
  std::atomic<std::uint64_t> scene_edits{0};   // scene edits answered (accepted or not: SceneGate counts)
};

class EngineSocket final : public net::WebSocketHandler, public Door {
 public:
  // Binds the address and port (throws std::runtime_error naming them and the reason).
  // cpus: where its thread runs (the gate's CPUs: off the loop's, no cross-CPU wake-up from the publisher).
  EngineSocket(const EngineSocketSettings& settings, Gate& gate, std::vector<int> cpus = {});
  ~EngineSocket() override;
  EngineSocket(const EngineSocket&) = delete;
  EngineSocket& operator=(const EngineSocket&) = delete;

  void start() override;
  void stop() override;  // idempotent
  [[nodiscard]] std::string url() const;
  [[nodiscard]] const EngineSocketCounters& counters() const noexcept { return counters_; }
  [[nodiscard]] const net::WebSocketCounters& connections() const noexcept { return server_->counters(); }

  // Door. A connection is the peer and its only channel: present while it is open.
  [[nodiscard]] DoorKind kind() const noexcept override { return DoorKind::socket; }
  [[nodiscard]] bool channel_open(const Sender& s) const override;
  [[nodiscard]] bool alive(const PeerId& p) override;
  // Publisher thread: device `device`'s newest state (sent to its subscribers; dropped for a client that lags).
  void state(std::size_t device, const DeviceSnapshot& snapshot, const hapticd_msg_DeviceState& s) override;
  // Any thread: a device's event, to the clients subscribed to its states.
  void event(const hapticd_msg_Event& e) override;
  // Service thread: answers the requests waiting.
  void answer_requests(RequestDispatcher& dispatcher) override;

  // The transport's calls (the socket thread).
  void opened(net::ConnectionId id) override;
  void received(net::ConnectionId id, std::string_view message, bool binary) override;
  void closed(net::ConnectionId id) override;
  [[nodiscard]] bool idle(net::ConnectionId id) const override;

  static constexpr std::size_t kRequestsPerClient = 8;  // waiting for an answer
  static constexpr std::size_t kRequests = 64;          // in all

 private:
  struct Client {
    std::string id;                // the client id its requests and commands carry
    std::vector<bool> subscribed;  // per device
    std::uint64_t serial = 0;      // its commands, numbered here (the gate wants them increasing)
    double allowance = 0.0;        // messages it may still send (a token bucket)
    std::int64_t refilled_ns = 0;
    std::size_t waiting = 0;  // requests waiting for an answer
    std::array<std::uint64_t, dds::kRejectReasons> rejections{};
    std::uint64_t malformed = 0, limited = 0;  // messages refused, dropped
  };
  struct Waiting {
    net::ConnectionId connection;
    hapticd_msg_ControlRequest request;
  };
  // Whether the client may send one more message now (the rate limit).
  bool allowed(Client& c, std::int64_t now_ns);
  // Tells the client what went wrong, the first time and then every 100th time.
  void tell(net::ConnectionId id, std::uint64_t count, std::string_view code, const std::string& message);
  // A scene edit (message_.scene) through the gate's SceneGate, answered on this connection.
  void edit_scene(net::ConnectionId id, Client& c);
  void subscribe(Client& c, const std::vector<std::string>& devices, net::ConnectionId id);
  void count_subscribers();
  [[nodiscard]] bool open(std::uint64_t connection) const;

  EngineSocketSettings settings_;
  Gate& gate_;
  DeviceGates& devices_;
  std::vector<socket_messages::InventoryDevice> inventory_;
  std::vector<socket_messages::InventoryGroup> groups_;
  std::uint64_t session_id_;
  std::unique_ptr<net::WebSocketServer> server_;
  EngineSocketCounters counters_;
  // The socket thread's.
  std::unordered_map<net::ConnectionId, Client> clients_;
  socket_messages::Parser parser_;
  socket_messages::ClientMessage message_;
  // Per device: whether any client subscribed (the publisher skips the JSON otherwise).
  std::unique_ptr<std::atomic<bool>[]> wanted_;
  // The connections open (from the handshake until closed): the gate's service thread asks.
  mutable std::mutex open_mutex_;
  std::vector<std::uint64_t> open_;
  // Requests waiting for the service thread.
  std::mutex waiting_mutex_;
  std::deque<Waiting> waiting_;
  std::string state_text_;  // the publisher thread's
};

}  // namespace hapticd::server
