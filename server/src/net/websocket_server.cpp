#include "net/websocket_server.hpp"

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>
#include <deque>
#include <optional>
#include <stdexcept>
#include <thread>
#include <type_traits>
#include <unordered_map>

namespace hapticd::server::net {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace ssl = asio::ssl;
using tcp = asio::ip::tcp;

namespace {

// Whether a Sec-WebSocket-Protocol header's comma-separated list offers `wanted`.
bool offers(std::string_view header, std::string_view wanted) {
  while (!header.empty()) {
    const std::size_t comma = header.find(',');
    std::string_view item = header.substr(0, comma);
    while (!item.empty() && (item.front() == ' ' || item.front() == '\t')) item.remove_prefix(1);
    while (!item.empty() && (item.back() == ' ' || item.back() == '\t')) item.remove_suffix(1);
    if (item == wanted) return true;
    if (comma == std::string_view::npos) break;
    header.remove_prefix(comma + 1);
  }
  return false;
}

std::string_view to_std(beast::string_view s) { return {s.data(), s.size()}; }

// Whether a page's Origin ("scheme://host[:port]") is served from this machine.
bool loopback_origin(std::string_view origin) {
  const std::size_t scheme = origin.find("://");
  if (scheme == std::string_view::npos) return false;
  std::string_view host = origin.substr(scheme + 3);
  if (host.substr(0, 5) == "[::1]") return host.size() == 5 || host[5] == ':';
  host = host.substr(0, host.find(':'));
  if (host == "localhost") return true;
  return loopback_address(host);
}

// The value of `name` in a request target's query ("/?token=abc&x=1"), "" when absent.
std::string_view query_value(std::string_view target, std::string_view name) {
  const std::size_t q = target.find('?');
  if (q == std::string_view::npos) return {};
  std::string_view query = target.substr(q + 1);
  while (!query.empty()) {
    const std::size_t amp = query.find('&');
    const std::string_view item = query.substr(0, amp);
    if (item.size() > name.size() && item.substr(0, name.size()) == name && item[name.size()] == '=')
      return item.substr(name.size() + 1);
    if (amp == std::string_view::npos) break;
    query.remove_prefix(amp + 1);
  }
  return {};
}

// Equal, in a time that does not depend on where they differ.
bool same_secret(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  unsigned char diff = 0;
  for (std::size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

}  // namespace

bool loopback_address(std::string_view address) {
  if (address == "::1") return true;
  return address.substr(0, 4) == "127." && address.find_first_not_of("0123456789.") == std::string_view::npos;
}

bool origin_allowed(std::string_view origin, const std::vector<std::string>& allowed) {
  if (origin.empty()) return true;  // not a browser page: a program, which could claim any origin anyway
  if (loopback_origin(origin)) return true;
  return std::find(allowed.begin(), allowed.end(), origin) != allowed.end();
}

std::string quoted(std::string_view text) {
  constexpr std::size_t kMax = 40;
  std::string out(text.substr(0, kMax));
  for (char& c : out)
    if (static_cast<unsigned char>(c) < 0x20 || c == '"' || c == '\\') c = '?';
  return text.size() > kMax ? out + "..." : out;
}

// A client's connection, whatever carries it (TCP, or TLS over TCP).
class Connection {
 public:
  virtual ~Connection() = default;
  virtual void start() = 0;
  virtual void close() = 0;
  virtual void send(std::shared_ptr<const std::string> data, bool binary, WebSocketServer::Kind kind) = 0;
  virtual void disconnect() = 0;
  virtual void check(std::chrono::steady_clock::time_point now) = 0;
  [[nodiscard]] virtual std::optional<std::chrono::steady_clock::duration> idle_for(
      std::chrono::steady_clock::time_point now) const = 0;
  [[nodiscard]] virtual bool opened() const noexcept = 0;
};

struct WebSocketServer::Impl {
  Impl(WebSocketOptions o, WebSocketHandler& h) : options(std::move(o)), handler(h), acceptor(io), timer(io) {}

  WebSocketOptions options;
  WebSocketHandler& handler;
  std::optional<ssl::context> tls;  // with a certificate and key: every connection speaks TLS
  asio::io_context io;
  tcp::acceptor acceptor;
  asio::steady_timer timer;
  std::chrono::nanoseconds period{};
  bool handler_ticks = false;
  std::chrono::steady_clock::time_point next_tick;
  std::unordered_map<ConnectionId, std::shared_ptr<Connection>> connections;
  ConnectionId next_id = 1;
  WebSocketCounters counters;
  std::thread thread;
  std::atomic<bool> running{false};
  bool stopped = false;

  void accept();
  void tick();
  void remove(ConnectionId id);
  // When every slot is taken: disconnects the client idle longest, past idle_grace; false if there is none.
  bool evict_idle_client();
};

// One client: the TLS handshake (with TLS), the HTTP upgrade, then its messages in and out (one write at a time, a
// bounded queue). Next: what the WebSocket runs on - beast::tcp_stream or beast::ssl_stream<beast::tcp_stream>.
template <class Next>
class StreamConnection final : public Connection, public std::enable_shared_from_this<StreamConnection<Next>> {
  static constexpr bool kTls = !std::is_same_v<Next, beast::tcp_stream>;

 public:
  StreamConnection(WebSocketServer::Impl& server, ConnectionId id, tcp::socket socket)
      : server_(server), id_(id), ws_(make_stream(server, std::move(socket))) {}

  void start() override {
    connected_at_ = std::chrono::steady_clock::now();
    beast::get_lowest_layer(ws_).expires_after(server_.options.handshake_timeout);
    if constexpr (kTls) {
      ws_.next_layer().async_handshake(
          ssl::stream_base::server, [self = this->shared_from_this()](beast::error_code ec) {
            if (ec) return self->server_.remove(self->id_);  // not TLS, or a handshake that failed: nothing to answer
            self->read_request();
          });
    } else {
      read_request();
    }
  }

  void close() override {
    beast::error_code ignored;
    beast::get_lowest_layer(ws_).socket().shutdown(tcp::socket::shutdown_both, ignored);
    beast::get_lowest_layer(ws_).close();
  }

  void send(std::shared_ptr<const std::string> data, bool binary, WebSocketServer::Kind kind) override {
    if (!open_) return;
    const WebSocketOptions& o = server_.options;
    const bool reply = kind == WebSocketServer::Kind::reply;
    if (queued_bytes_ + data->size() > o.max_queued_bytes) {
      if (reply) return disconnect();
      server_.counters.dropped.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    if (reply && queued_replies_ >= o.max_queued_replies) return disconnect();
    if (queue_.empty()) last_progress_ = std::chrono::steady_clock::now();
    queued_bytes_ += data->size();
    if (reply) ++queued_replies_;
    queue_.push_back({std::move(data), binary, reply});
    server_.counters.sent.fetch_add(1, std::memory_order_relaxed);
    if (queue_.size() == 1) write_next();
  }

  // Closes the connection; the failing read then removes the client (not here: the handler may be iterating).
  void disconnect() override {
    if (closing_) return;
    closing_ = true;
    open_ = false;
    server_.counters.disconnected.fetch_add(1, std::memory_order_relaxed);
    close();
  }

  // Too slow (nothing taken for slow_timeout while messages wait), or idle since it connected: disconnected.
  void check(std::chrono::steady_clock::time_point now) override {
    const WebSocketOptions& o = server_.options;
    if (!queue_.empty() && now - last_progress_ > o.slow_timeout) return disconnect();
    if (opened_ && server_.handler.idle(id_) && now - connected_at_ > o.idle_timeout) return disconnect();
  }
  [[nodiscard]] std::optional<std::chrono::steady_clock::duration> idle_for(
      std::chrono::steady_clock::time_point now) const override {
    if (closing_ || (opened_ && !server_.handler.idle(id_))) return std::nullopt;
    return now - connected_at_;
  }
  [[nodiscard]] bool opened() const noexcept override { return opened_; }

 private:
  static websocket::stream<Next> make_stream(WebSocketServer::Impl& server, tcp::socket socket) {
    if constexpr (kTls)
      return websocket::stream<Next>(beast::tcp_stream(std::move(socket)), *server.tls);
    else
      return websocket::stream<Next>(std::move(socket));
  }

  void read_request() {
    http::async_read(ws_.next_layer(), buffer_, request_,
                     [self = this->shared_from_this()](beast::error_code ec, std::size_t) { self->on_request(ec); });
  }

  struct Outgoing {
    std::shared_ptr<const std::string> data;
    bool binary;
    bool reply;
  };

  void on_request(beast::error_code ec) {
    if (ec) return server_.remove(id_);
    const WebSocketOptions& o = server_.options;
    if (!origin_allowed(to_std(request_[http::field::origin]), o.allowed_origins)) {
      server_.counters.refused.fetch_add(1, std::memory_order_relaxed);
      return refuse(http::status::forbidden, "a page from " + quoted(to_std(request_[http::field::origin])) +
                                                 " may not connect to the " + o.what +
                                                 ": pages served from this machine may, and " + o.origin_hint + "\n");
    }
    if (!websocket::is_upgrade(request_) && request_.method() == http::verb::get && !o.pages.empty()) {
      const std::string_view target = to_std(request_.target());
      const std::string_view path = target.substr(0, target.find('?'));
      if (path == "/") return serve_page(o.pages.front());
      for (const WebSocketOptions::Page& page : o.pages)
        if (path == page.path) return serve_page(page);
    }
    if (!o.token.empty()) {
      std::string_view given = query_value(to_std(request_.target()), "token");
      const std::string_view authorization = to_std(request_[http::field::authorization]);
      if (given.empty() && authorization.substr(0, 7) == "Bearer ") given = authorization.substr(7);
      if (!same_secret(given, o.token)) {
        server_.counters.refused.fetch_add(1, std::memory_order_relaxed);
        return refuse(http::status::unauthorized,
                      "the " + o.what + " needs its access token: ?token=... in the URL or Authorization: Bearer\n");
      }
    }
    if (!websocket::is_upgrade(request_) ||
        (!o.subprotocol.empty() && !offers(to_std(request_[http::field::sec_websocket_protocol]), o.subprotocol))) {
      server_.counters.refused.fetch_add(1, std::memory_order_relaxed);
      return refuse(http::status::bad_request, o.subprotocol_hint + "\n");
    }
    beast::get_lowest_layer(ws_).expires_never();
    websocket::stream_base::timeout timeouts = websocket::stream_base::timeout::suggested(beast::role_type::server);
    if (o.keepalive_timeout.count() > 0) {
      timeouts.idle_timeout = o.keepalive_timeout;
      timeouts.keep_alive_pings = true;
    }
    ws_.set_option(timeouts);
    ws_.set_option(websocket::stream_base::decorator([&o](websocket::response_type& response) {
      if (!o.subprotocol.empty()) response.set(http::field::sec_websocket_protocol, o.subprotocol);
      response.set(http::field::server, o.server_header);
    }));
    ws_.read_message_max(o.max_message_bytes);
    ws_.async_accept(request_, [self = this->shared_from_this()](beast::error_code e) { self->on_accepted(e); });
  }

  void serve_page(const WebSocketOptions::Page& page) {
    respond(http::status::ok, "text/html; charset=utf-8", std::string(page.html));
  }

  void refuse(http::status status, std::string text) { respond(status, "text/plain", std::move(text)); }

  // A plain HTTP answer, then the connection closes.
  void respond(http::status status, const char* content_type, std::string body) {
    auto response = std::make_shared<http::response<http::string_body>>(status, request_.version());
    response->set(http::field::content_type, content_type);
    response->set(http::field::cache_control, "no-store");
    // No other page may frame what is served here (a framed wall page claimed a device for another site): CSP's
    // frame-ancestors, and X-Frame-Options for browsers without it.
    response->set("Content-Security-Policy", "frame-ancestors 'none'");
    response->set(http::field::x_frame_options, "DENY");
    response->set("X-Content-Type-Options", "nosniff");
    response->body() = std::move(body);
    response->prepare_payload();
    response->keep_alive(false);
    http::async_write(ws_.next_layer(), *response,
                      [self = this->shared_from_this(), response](beast::error_code, std::size_t) {
                        self->close();
                        self->server_.remove(self->id_);
                      });
  }

  void on_accepted(beast::error_code ec) {
    if (ec) return server_.remove(id_);
    open_ = true;
    opened_ = true;
    server_.counters.connections.fetch_add(1, std::memory_order_relaxed);
    server_.handler.opened(id_);
    read_next();
  }

  void read_next() {
    ws_.async_read(in_, [self = this->shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
  }

  void on_read(beast::error_code ec) {
    if (ec) {
      open_ = false;
      return server_.remove(id_);
    }
    const auto data = in_.cdata();
    server_.handler.received(id_, std::string_view(static_cast<const char*>(data.data()), data.size()),
                             !ws_.got_text());
    in_.consume(in_.size());
    if (open_) read_next();
  }

  void write_next() {
    const Outgoing& next = queue_.front();
    ws_.binary(next.binary);
    ws_.async_write(asio::buffer(*next.data), [self = this->shared_from_this()](beast::error_code ec, std::size_t) {
      self->queued_bytes_ -= self->queue_.front().data->size();
      if (self->queue_.front().reply) --self->queued_replies_;
      self->queue_.pop_front();
      self->last_progress_ = std::chrono::steady_clock::now();
      if (ec) {
        self->open_ = false;
        self->queue_.clear();
        self->queued_bytes_ = 0;
        self->queued_replies_ = 0;
        return self->server_.remove(self->id_);
      }
      if (!self->queue_.empty()) self->write_next();
    });
  }

  WebSocketServer::Impl& server_;
  ConnectionId id_;
  websocket::stream<Next> ws_;
  beast::flat_buffer buffer_, in_;
  http::request<http::string_body> request_;
  bool open_ = false;    // messages may be queued
  bool opened_ = false;  // the handler was told
  bool closing_ = false;
  std::deque<Outgoing> queue_;
  std::size_t queued_bytes_ = 0;
  std::size_t queued_replies_ = 0;
  std::chrono::steady_clock::time_point connected_at_, last_progress_;
};

void WebSocketServer::Impl::accept() {
  acceptor.async_accept([this](beast::error_code ec, tcp::socket socket) {
    if (ec) {
      if (!stopped) accept();
      return;
    }
    if (static_cast<int>(connections.size()) >= options.max_clients && !evict_idle_client()) {
      counters.refused.fetch_add(1, std::memory_order_relaxed);
      beast::error_code ignored;
      socket.shutdown(tcp::socket::shutdown_both, ignored);
      socket.close(ignored);
    } else {
      beast::error_code ignored;
      if (options.send_buffer_bytes > 0)
        socket.set_option(asio::socket_base::send_buffer_size(options.send_buffer_bytes), ignored);
      socket.set_option(tcp::no_delay(true), ignored);  // small messages, each as soon as it is written
      const ConnectionId id = next_id++;
      std::shared_ptr<Connection> c;
      if (tls)
        c = std::make_shared<StreamConnection<beast::ssl_stream<beast::tcp_stream>>>(*this, id, std::move(socket));
      else
        c = std::make_shared<StreamConnection<beast::tcp_stream>>(*this, id, std::move(socket));
      connections.emplace(id, c);
      counters.clients.store(connections.size(), std::memory_order_relaxed);
      c->start();
    }
    accept();
  });
}

bool WebSocketServer::Impl::evict_idle_client() {
  const auto now = std::chrono::steady_clock::now();
  Connection* longest = nullptr;
  std::chrono::steady_clock::duration idle{};
  for (const auto& [id, c] : connections)
    if (const auto d = c->idle_for(now); d && *d > options.idle_grace && *d > idle) {
      idle = *d;
      longest = c.get();
    }
  if (longest == nullptr) return false;
  longest->disconnect();  // its slot is free once its read fails
  return true;
}

void WebSocketServer::Impl::remove(ConnectionId id) {
  const auto it = connections.find(id);
  if (it == connections.end()) return;
  const std::shared_ptr<Connection> c = it->second;  // alive until the handler has been told
  connections.erase(it);
  counters.clients.store(connections.size(), std::memory_order_relaxed);
  if (c->opened() && !stopped) handler.closed(id);
}

void WebSocketServer::Impl::tick() {
  if (stopped) return;
  const auto checked = std::chrono::steady_clock::now();
  for (const auto& [id, c] : connections) c->check(checked);  // disconnects only: removal comes with the read
  if (handler_ticks && !connections.empty()) {
    try {  // a tick that fails (memory) loses this tick's messages, not the next ticks
      handler.tick();
    } catch (...) {
      counters.dropped.fetch_add(1, std::memory_order_relaxed);
    }
  }
  // Fixed rate: the next tick from the planned time (a late one is not made up for).
  const auto now = std::chrono::steady_clock::now();
  next_tick += period;
  if (next_tick < now) next_tick = now + period;
  timer.expires_at(next_tick);
  timer.async_wait([this](beast::error_code ec) {
    if (!ec) tick();
  });
}

WebSocketServer::WebSocketServer(WebSocketOptions options, WebSocketHandler& handler)
    : impl_(std::make_shared<Impl>(std::move(options), handler)) {
  Impl& s = *impl_;
  const std::string where = s.options.address + ":" + std::to_string(s.options.port);
  beast::error_code ec;
  const asio::ip::address address = asio::ip::make_address(s.options.address, ec);
  if (ec) throw std::runtime_error(s.options.what + ": '" + s.options.address + "' is not an IP address");
  const tcp::endpoint endpoint(address, static_cast<unsigned short>(s.options.port));
  s.acceptor.open(endpoint.protocol(), ec);
  if (!ec) s.acceptor.set_option(asio::socket_base::reuse_address(true), ec);
  if (!ec) s.acceptor.bind(endpoint, ec);
  if (!ec) s.acceptor.listen(asio::socket_base::max_listen_connections, ec);
  if (ec) throw std::runtime_error(s.options.what + ": cannot listen on " + where + ": " + ec.message());
  if (!s.options.tls_certificate_file.empty()) {
    s.tls.emplace(ssl::context::tls_server);
    s.tls->set_options(ssl::context::default_workarounds | ssl::context::no_sslv2 | ssl::context::no_sslv3 |
                       ssl::context::no_tlsv1 | ssl::context::no_tlsv1_1);
    s.tls->use_certificate_chain_file(s.options.tls_certificate_file, ec);
    if (ec)
      throw std::runtime_error(s.options.what + ": cannot use the certificate " + s.options.tls_certificate_file +
                               ": " + ec.message());
    s.tls->use_private_key_file(s.options.tls_private_key_file, ssl::context::pem, ec);
    if (ec)
      throw std::runtime_error(s.options.what + ": cannot use the private key " + s.options.tls_private_key_file +
                               ": " + ec.message());
  }
}

WebSocketServer::~WebSocketServer() { stop(); }

int WebSocketServer::port() const noexcept {
  beast::error_code ec;
  const tcp::endpoint e = impl_->acceptor.local_endpoint(ec);
  return ec ? -1 : e.port();
}

const WebSocketCounters& WebSocketServer::counters() const noexcept { return impl_->counters; }
const WebSocketOptions& WebSocketServer::options() const noexcept { return impl_->options; }

void WebSocketServer::start(std::chrono::nanoseconds tick_period) {
  Impl& s = *impl_;
  s.handler_ticks = tick_period.count() > 0;
  s.period = s.handler_ticks ? tick_period : std::chrono::milliseconds(250);  // the connections' checks at least
  s.next_tick = std::chrono::steady_clock::now();
  s.accept();
  s.tick();
  s.thread = std::thread([&s] {
    if (!s.options.cpus.empty()) {
      cpu_set_t set;
      CPU_ZERO(&set);
      for (int c : s.options.cpus) CPU_SET(c, &set);
      (void)pthread_setaffinity_np(pthread_self(), sizeof set, &set);
    }
    // A handler that throws (memory) loses its client's message or request, never the thread: it runs on.
    for (;;) {
      try {
        s.io.run();
        return;
      } catch (...) {
        s.counters.bad_requests.fetch_add(1, std::memory_order_relaxed);
      }
    }
  });
  s.running.store(true, std::memory_order_release);
}

void WebSocketServer::stop() {
  Impl& s = *impl_;
  if (s.thread.joinable()) {
    s.running.store(false, std::memory_order_release);
    asio::post(s.io, [&s] {
      s.stopped = true;
      beast::error_code ignored;
      s.acceptor.close(ignored);
      s.timer.cancel();
      for (const auto& [id, c] : s.connections) c->close();
      s.connections.clear();
      s.io.stop();
    });
    s.thread.join();
  }
  s.counters.clients.store(0, std::memory_order_relaxed);
}

void WebSocketServer::send(ConnectionId id, std::shared_ptr<const std::string> message, bool binary, Kind kind) {
  const auto it = impl_->connections.find(id);
  if (it != impl_->connections.end()) it->second->send(std::move(message), binary, kind);
}

void WebSocketServer::disconnect(ConnectionId id) {
  const auto it = impl_->connections.find(id);
  if (it != impl_->connections.end()) it->second->disconnect();
}

void WebSocketServer::count_bad_request() noexcept {
  impl_->counters.bad_requests.fetch_add(1, std::memory_order_relaxed);
}

bool WebSocketServer::post(std::function<void()> f) {
  if (!impl_->running.load(std::memory_order_acquire)) return false;
  asio::post(impl_->io, std::move(f));
  return true;
}

}  // namespace hapticd::server::net
