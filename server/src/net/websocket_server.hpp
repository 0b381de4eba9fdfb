#pragma once
// A hardened WebSocket server, the transport under the live view (Foxglove's protocol) and the engine socket
// (hapticd's JSON protocol for clients without DDS): listens on one address, accepts clients up to a limit,
// speaks TLS when given a certificate, checks each upgrade (the page's Origin, an access token, a subprotocol), and
// hands each client's messages to a protocol handler, which answers through send(). One thread of its own runs every
// socket, calls the handler and its tick at a fixed period. A client that cannot keep up loses data messages (counted),
// never the server's memory or time: everything queued for a client is bounded, and one that stops taking what it is
// sent, or stays idle (by the handler's measure), is disconnected. Boost.Beast lives in this one file's implementation.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hapticd::server::net {

using ConnectionId = std::uint64_t;

struct WebSocketOptions {
  std::string what = "WebSocket server";  // in messages: "live view", "engine socket"
  std::string address = "127.0.0.1";
  int port = 0;  // 0: any free port (port() tells)
  int max_clients = 4;
  std::string server_header = "hapticd";
  // A subprotocol every client must offer ("": none), and what a client that does not is told.
  std::string subprotocol;
  std::string subprotocol_hint;
  // When not empty, a client must present this token: "?token=..." in its URL (browsers cannot set headers on a
  // WebSocket) or "Authorization: Bearer ...". Compared in constant time.
  std::string token;
  // TLS (wss://) with this certificate chain and private key (PEM files); empty: plain WebSocket (ws://).
  std::string tls_certificate_file, tls_private_key_file;
  // Per client, everything queued for it (data and replies): above it data messages are dropped; a reply that
  // does not fit, or a client that has not taken a message for slow_timeout, is disconnected.
  std::size_t max_queued_bytes = 8u << 20;
  std::size_t max_queued_replies = 32;  // replies waiting: more means the client does not read them
  std::size_t max_message_bytes = 64u << 10;
  int send_buffer_bytes = 0;  // the kernel's send buffer per client (SO_SNDBUF); 0: the system's default
  std::chrono::milliseconds slow_timeout{3000};
  // A client idle (the handler says) this long after its handshake is disconnected; and when every slot is taken,
  // a new client takes the slot of the one idle longest (after idle_grace).
  std::chrono::milliseconds idle_timeout{10000};
  std::chrono::milliseconds idle_grace{1000};
  std::chrono::seconds handshake_timeout{5};
  // The CPUs the server's thread runs on (empty: any).
  std::vector<int> cpus;
  // A connection that answers no ping for this long is closed (a frozen or vanished peer); 0: Beast's default.
  std::chrono::milliseconds keepalive_timeout{0};
  // Web pages that may connect (their Origin header): pages served from loopback always may, and these (e.g.
  // "https://app.foxglove.dev"); a client without an Origin (a program, not a browser page) always may.
  std::vector<std::string> allowed_origins;
  std::string origin_hint;  // where the refusal of an origin tells the user to list it
  // Pages served to a plain HTTP GET of their paths (a query after the path is the page's); "/" serves the first.
  struct Page {
    std::string path;  // "/wall.html"
    std::string_view html;
  };
  std::vector<Page> pages;
};

struct WebSocketCounters {
  std::atomic<std::uint64_t> connections{0};  // clients accepted so far
  std::atomic<std::uint64_t> refused{0};      // refused: too many clients, bad token, origin or protocol
  std::atomic<std::uint64_t> clients{0};      // connected now
  std::atomic<std::uint64_t> sent{0};         // messages queued for sending
  std::atomic<std::uint64_t> dropped{0};      // data messages a slow client did not get
  std::atomic<std::uint64_t> bad_requests{0};
  std::atomic<std::uint64_t> disconnected{0};  // clients cut off: too slow, never reading, or idle
};

// Whether a browser page from `origin` (its Origin header; empty: not a page) may connect: loopback pages and
// the listed ones.
[[nodiscard]] bool origin_allowed(std::string_view origin, const std::vector<std::string>& allowed);
// A client's text as a reply may quote it: a few words, never what it sent in full.
[[nodiscard]] std::string quoted(std::string_view text);
// Whether `address` is a loopback address (127.0.0.0/8, ::1).
[[nodiscard]] bool loopback_address(std::string_view address);

// What a protocol does with its clients. Every call comes on the server's thread.
class WebSocketHandler {
 public:
  virtual ~WebSocketHandler() = default;
  virtual void opened(ConnectionId id) = 0;  // the handshake is done: the handler may send
  virtual void received(ConnectionId id, std::string_view message, bool binary) = 0;
  virtual void closed(ConnectionId id) = 0;  // after opened(): the connection is gone
  // Whether the client holds its slot for nothing (idle_timeout, and eviction when every slot is taken).
  [[nodiscard]] virtual bool idle(ConnectionId id) const = 0;
  virtual void tick() {}
};

class WebSocketServer {
 public:
  // Binds and listens; throws std::runtime_error naming the address, the port and the reason.
  WebSocketServer(WebSocketOptions options, WebSocketHandler& handler);
  ~WebSocketServer();  // stop()
  WebSocketServer(const WebSocketServer&) = delete;
  WebSocketServer& operator=(const WebSocketServer&) = delete;

  [[nodiscard]] int port() const noexcept;
  [[nodiscard]] const WebSocketCounters& counters() const noexcept;
  [[nodiscard]] const WebSocketOptions& options() const noexcept;

  // Starts the server's thread; the handler's tick runs every `tick_period` (0: never).
  void start(std::chrono::nanoseconds tick_period = {});
  // Closes every connection and joins the thread (idempotent).
  void stop();

  enum class Kind : std::uint8_t {
    data,  // dropped (counted) when the client's queue is full
    reply  // must arrive: a client whose queue holds no room for it is disconnected
  };
  // Server thread only: queues a message for a client (nothing when it is gone).
  void send(ConnectionId id, std::shared_ptr<const std::string> message, bool binary, Kind kind);
  // Server thread only: closes a client's connection (closed() follows).
  void disconnect(ConnectionId id);
  // A message the handler refused (counted).
  void count_bad_request() noexcept;
  // Any thread: runs `f` on the server's thread (false: the server is not running).
  bool post(std::function<void()> f);

  struct Impl;

 private:
  std::shared_ptr<Impl> impl_;
};

}  // namespace hapticd::server::net
