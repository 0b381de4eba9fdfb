#pragma once
// A Foxglove WebSocket server (foxglove.websocket.v1, JSON channels): listens on one address, accepts viewers up
// to a limit, tells each the server info and the channels, keeps their subscriptions, and sends each message
// published on a channel to whoever subscribed to it. One thread of its own runs every socket and calls the
// owner's tick at a fixed period; publish() is called from that tick. A viewer that cannot keep up loses
// messages (counted), never the server's memory or time; a malformed request is answered with an error status
// and counted, and the viewer stays connected. Boost.Beast lives in this one file's implementation.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "live_view/foxglove_protocol.hpp"

namespace hapticd::server::live_view {

struct FoxgloveServerOptions {
  std::string address = "127.0.0.1";
  int port = 8765;  // 0: any free port (port() tells)
  int max_clients = 4;
  std::string name = "hapticd";             // the server info's name
  std::size_t max_queued_bytes = 8u << 20;  // per viewer; above it its messages are dropped
  std::chrono::seconds handshake_timeout{5};
};

struct FoxgloveServerCounters {
  std::atomic<std::uint64_t> connections{0};  // viewers accepted so far
  std::atomic<std::uint64_t> refused{0};      // connections refused: too many viewers, or not the protocol
  std::atomic<std::uint64_t> clients{0};      // connected now
  std::atomic<std::uint64_t> sent{0};         // messages queued for sending
  std::atomic<std::uint64_t> dropped{0};      // messages a slow viewer did not get
  std::atomic<std::uint64_t> bad_requests{0};
};

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

  struct Impl;

 private:
  std::shared_ptr<Impl> impl_;
};

}  // namespace hapticd::server::live_view
