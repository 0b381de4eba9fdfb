#pragma once
// A Foxglove WebSocket server (foxglove.websocket.v1, JSON channels) on the hardened WebSocket transport
// (net/websocket_server.hpp: client limit, origins, bounded queues, slow and idle clients cut off): tells each
// viewer the server info and the channels, keeps their subscriptions, and sends each message published on a
// channel to whoever subscribed to it. The transport's thread calls the owner's tick at a fixed period; publish()
// is called from that tick. A viewer that subscribes to nothing is idle. A malformed request is answered with an
// error status (never echoing more than a few words of it) and counted.
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "live_view/foxglove_protocol.hpp"
#include "net/websocket_server.hpp"

namespace hapticd::server::live_view {

struct FoxgloveServerOptions {
  std::string address = "127.0.0.1";
  int port = 8765;  // 0: any free port (port() tells)
  int max_clients = 4;
  std::string name = "hapticd";  // the server info's name
  // Per viewer, everything queued for it (data and replies): above it data messages are dropped; a reply that
  // does not fit, or a viewer that has not taken a message for slow_viewer_timeout, is disconnected.
  std::size_t max_queued_bytes = 8u << 20;
  std::size_t max_queued_replies = 32;  // status replies waiting: more means the viewer does not read them
  std::chrono::milliseconds slow_viewer_timeout{3000};
  // A viewer that has subscribed to nothing this long after its handshake is disconnected; and when every slot
  // is taken, a new viewer takes the slot of the one idle longest (after idle_grace).
  std::chrono::milliseconds idle_timeout{10000};
  std::chrono::milliseconds idle_grace{1000};
  std::chrono::seconds handshake_timeout{5};
  // Web pages that may connect (their Origin header): pages served from loopback always may, and these (e.g.
  // "https://app.foxglove.dev"); a client without an Origin (a program, not a browser page) always may.
  std::vector<std::string> allowed_origins;
  // A page served to a plain HTTP GET of "/" (the live view's own viewer; empty: none).
  std::string_view page;
};

using FoxgloveServerCounters = net::WebSocketCounters;
using net::origin_allowed;

class FoxgloveServer {
 public:
  // Binds and listens; throws std::runtime_error naming the address, the port and the reason.
  FoxgloveServer(FoxgloveServerOptions options, std::vector<Channel> channels);
  ~FoxgloveServer();  // stop()
  FoxgloveServer(const FoxgloveServer&) = delete;
  FoxgloveServer& operator=(const FoxgloveServer&) = delete;

  [[nodiscard]] int port() const noexcept;
  [[nodiscard]] const FoxgloveServerCounters& counters() const noexcept;

  // Starts the server's thread: it serves the viewers and calls on_tick every `period`.
  void start(std::chrono::nanoseconds period, std::function<void()> on_tick);
  // Closes every connection and joins the thread (idempotent).
  void stop();

  // From on_tick only (the server's thread): whether anyone subscribed to the channel, and a message for it.
  [[nodiscard]] bool subscribed(std::uint32_t channel) const noexcept;
  void publish(std::uint32_t channel, std::uint64_t time_ns, std::string_view payload);

  class Protocol;

 private:
  std::unique_ptr<Protocol> protocol_;
  std::unique_ptr<net::WebSocketServer> transport_;
};

}  // namespace hapticd::server::live_view
