#include "live_view/foxglove_server.hpp"

#include <algorithm>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <deque>
#include <optional>
#include <stdexcept>
#include <thread>
#include <unordered_map>

namespace hapticd::server::live_view {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
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

// A viewer's text as a reply may quote it: a few words, never what it sent in full.
std::string quoted(std::string_view text) {
  constexpr std::size_t kMax = 40;
  std::string out(text.substr(0, kMax));
  for (char& c : out)
    if (static_cast<unsigned char>(c) < 0x20 || c == '"' || c == '\\') c = '?';
  return text.size() > kMax ? out + "..." : out;
}

// Whether a page's Origin ("scheme://host[:port]") is served from this machine.
bool loopback_origin(std::string_view origin) {
  const std::size_t scheme = origin.find("://");
  if (scheme == std::string_view::npos) return false;
  std::string_view host = origin.substr(scheme + 3);
  if (host.substr(0, 5) == "[::1]") return host.size() == 5 || host[5] == ':';
  host = host.substr(0, host.find(':'));
  if (host == "localhost") return true;
  return host.substr(0, 4) == "127." && host.find_first_not_of("0123456789.") == std::string_view::npos;
}

}  // namespace

bool origin_allowed(std::string_view origin, const std::vector<std::string>& allowed) {
  if (origin.empty()) return true;  // not a browser page: a program, which could claim any origin anyway
  if (loopback_origin(origin)) return true;
  return std::find(allowed.begin(), allowed.end(), origin) != allowed.end();
}

namespace {}  // namespace

class Viewer;

struct FoxgloveServer::Impl {
  Impl(FoxgloveServerOptions o, std::vector<Channel> c)
      : options(std::move(o)), channels(std::move(c)), acceptor(io), timer(io) {}

  FoxgloveServerOptions options;
  std::vector<Channel> channels;
  std::string server_info, advertise;
  asio::io_context io;
  tcp::acceptor acceptor;
  asio::steady_timer timer;
  std::chrono::nanoseconds period{};
  std::chrono::steady_clock::time_point next_tick;
  std::function<void()> on_tick;
  std::vector<std::shared_ptr<Viewer>> viewers;
  FoxgloveServerCounters counters;
  std::thread thread;
  bool stopped = false;
  std::string frame;  // reused for each message's binary frame

  void accept();
  void tick();
  void remove(const Viewer* viewer);
  // When every slot is taken: disconnects the viewer idle (subscribed to nothing) longest, past idle_grace; false
  // if there is none.
  bool evict_idle_viewer();
  [[nodiscard]] bool has_channel(std::uint32_t id) const {
    return std::any_of(channels.begin(), channels.end(), [&](const Channel& c) { return c.id == id; });
  }
};

// One connected viewer: the HTTP upgrade, then its messages in and out (one write at a time, a bounded queue).
class Viewer : public std::enable_shared_from_this<Viewer> {
 public:
  Viewer(FoxgloveServer::Impl& server, tcp::socket socket) : server_(server), ws_(std::move(socket)) {}

  void start() {
    connected_at_ = std::chrono::steady_clock::now();
    beast::get_lowest_layer(ws_).expires_after(server_.options.handshake_timeout);
    http::async_read(beast::get_lowest_layer(ws_), buffer_, request_,
                     [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_request(ec); });
  }

  void close() {
    beast::error_code ignored;
    beast::get_lowest_layer(ws_).socket().shutdown(tcp::socket::shutdown_both, ignored);
    beast::get_lowest_layer(ws_).close();
  }

  // Queues a message. Data (binary) is dropped and counted when the queue is full; a reply (text) that does not
  // fit, or one past max_queued_replies, disconnects the viewer: it sends requests and does not read the answers.
  void send(std::shared_ptr<const std::string> data, bool binary) {
    if (!open_) return;
    const FoxgloveServerOptions& o = server_.options;
    if (queued_bytes_ + data->size() > o.max_queued_bytes) {
      if (!binary) return disconnect();
      server_.counters.dropped.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    if (!binary && queued_replies_ >= o.max_queued_replies) return disconnect();
    if (queue_.empty()) last_progress_ = std::chrono::steady_clock::now();
    queued_bytes_ += data->size();
    if (!binary) ++queued_replies_;
    queue_.push_back({std::move(data), binary});
    server_.counters.sent.fetch_add(1, std::memory_order_relaxed);
    if (queue_.size() == 1) write_next();
  }

  // Closes the connection; the failing read then removes the viewer (not here: publish may be iterating).
  void disconnect() {
    if (closing_) return;
    closing_ = true;
    open_ = false;
    server_.counters.disconnected.fetch_add(1, std::memory_order_relaxed);
    close();
  }

  // Too slow (nothing taken for slow_viewer_timeout while messages wait), or idle (no subscription
  // idle_timeout after connecting): disconnected.
  void check(std::chrono::steady_clock::time_point now) {
    const FoxgloveServerOptions& o = server_.options;
    if (!queue_.empty() && now - last_progress_ > o.slow_viewer_timeout) return disconnect();
    if (subscriptions_.empty() && now - connected_at_ > o.idle_timeout) return disconnect();
  }
  // Subscribed to nothing since it connected this long ago (a candidate to give its slot to a new viewer).
  [[nodiscard]] std::optional<std::chrono::steady_clock::duration> idle_for(
      std::chrono::steady_clock::time_point now) const {
    if (!subscriptions_.empty() || closing_) return std::nullopt;
    return now - connected_at_;
  }

  // The subscriptions of this viewer on a channel (their ids), for publish.
  template <typename F>
  void for_each_subscription(std::uint32_t channel, F&& f) const {
    for (const auto& [id, ch] : subscriptions_)
      if (ch == channel) f(id);
  }
  [[nodiscard]] bool subscribed(std::uint32_t channel) const {
    return std::any_of(subscriptions_.begin(), subscriptions_.end(),
                       [&](const auto& s) { return s.second == channel; });
  }

 private:
  struct Outgoing {
    std::shared_ptr<const std::string> data;
    bool binary;
  };

  void on_request(beast::error_code ec) {
    if (ec) return server_.remove(this);
    if (!origin_allowed(to_std(request_[http::field::origin]), server_.options.allowed_origins)) {
      server_.counters.refused.fetch_add(1, std::memory_order_relaxed);
      return refuse(http::status::forbidden,
                    "a page from " + quoted(to_std(request_[http::field::origin])) +
                        " may not watch this session: pages served from this machine may, and the origins listed "
                        "in the session's live_view.allowed_origins\n");
    }
    if (!websocket::is_upgrade(request_) && request_.method() == http::verb::get && !server_.options.page.empty()) {
      const std::string_view target = to_std(request_.target());
      if (target == "/" || target.substr(0, 2) == "/?" || target.substr(0, 12) == "/viewer.html") return serve_page();
    }
    if (!websocket::is_upgrade(request_) ||
        !offers(to_std(request_[http::field::sec_websocket_protocol]), kSubprotocol)) {
      server_.counters.refused.fetch_add(1, std::memory_order_relaxed);
      return refuse(http::status::bad_request,
                    "hapticd's live view speaks the Foxglove WebSocket protocol: connect with the subprotocol " +
                        std::string(kSubprotocol) + " (Foxglove or Lichtblick: Open connection, Foxglove WebSocket)\n");
    }
    beast::get_lowest_layer(ws_).expires_never();
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.set_option(websocket::stream_base::decorator([](websocket::response_type& response) {
      response.set(http::field::sec_websocket_protocol, beast::string_view(kSubprotocol.data(), kSubprotocol.size()));
      response.set(http::field::server, "hapticd live view");
    }));
    ws_.read_message_max(kMaxClientMessageBytes);
    ws_.async_accept(request_, [self = shared_from_this()](beast::error_code e) { self->on_accepted(e); });
  }

  void serve_page() { respond(http::status::ok, "text/html; charset=utf-8", std::string(server_.options.page)); }

  void refuse(http::status status, std::string text) { respond(status, "text/plain", std::move(text)); }

  // A plain HTTP answer, then the connection closes.
  void respond(http::status status, const char* content_type, std::string body) {
    auto response = std::make_shared<http::response<http::string_body>>(status, request_.version());
    response->set(http::field::content_type, content_type);
    response->set(http::field::cache_control, "no-store");
    response->body() = std::move(body);
    response->prepare_payload();
    response->keep_alive(false);
    http::async_write(beast::get_lowest_layer(ws_), *response,
                      [self = shared_from_this(), response](beast::error_code, std::size_t) {
                        self->close();
                        self->server_.remove(self.get());
                      });
  }

  void on_accepted(beast::error_code ec) {
    if (ec) return server_.remove(this);
    open_ = true;
    server_.counters.connections.fetch_add(1, std::memory_order_relaxed);
    send(std::make_shared<const std::string>(server_.server_info), false);
    send(std::make_shared<const std::string>(server_.advertise), false);
    read_next();
  }

  void read_next() {
    ws_.async_read(in_, [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
  }

  void on_read(beast::error_code ec) {
    if (ec) {
      open_ = false;
      return server_.remove(this);
    }
    if (ws_.got_text()) {
      const std::string text = beast::buffers_to_string(in_.data());
      handle(parse_client_request(text));
    } else {
      reply_error(1, "binary messages from viewers are not taken (this server offers no client publishing)");
    }
    in_.consume(in_.size());
    read_next();
  }

  void reply_error(int level, const std::string& text) {
    server_.counters.bad_requests.fetch_add(1, std::memory_order_relaxed);
    send(std::make_shared<const std::string>(status_message(level, text)), false);
  }

  void handle(const ClientRequest& r) {
    switch (r.kind) {
      case ClientRequest::Kind::invalid:
        return reply_error(2, "request refused: " + r.error);
      case ClientRequest::Kind::unsupported:
        return reply_error(
            1, "'" + quoted(r.op) + "' is not offered by this server (it offers subscribe and unsubscribe)");
      case ClientRequest::Kind::subscribe:
        for (const Subscription& s : r.subscriptions) {
          if (!server_.has_channel(s.channel))
            reply_error(2, "subscribe: no channel " + std::to_string(s.channel));
          else if (subscriptions_.count(s.id) != 0)
            reply_error(2, "subscribe: subscription id " + std::to_string(s.id) + " is in use");
          else if (subscriptions_.size() >= 4 * server_.channels.size())
            reply_error(2, "subscribe: too many subscriptions");
          else
            subscriptions_.emplace(s.id, s.channel);
        }
        return;
      case ClientRequest::Kind::unsubscribe:
        for (const std::uint32_t id : r.subscription_ids) subscriptions_.erase(id);
        return;
    }
  }

  void write_next() {
    const Outgoing& next = queue_.front();
    ws_.binary(next.binary);
    ws_.async_write(asio::buffer(*next.data), [self = shared_from_this()](beast::error_code ec, std::size_t) {
      self->queued_bytes_ -= self->queue_.front().data->size();
      if (!self->queue_.front().binary) --self->queued_replies_;
      self->queue_.pop_front();
      self->last_progress_ = std::chrono::steady_clock::now();
      if (ec) {
        self->open_ = false;
        self->queue_.clear();
        self->queued_bytes_ = 0;
        self->queued_replies_ = 0;
        return self->server_.remove(self.get());
      }
      if (!self->queue_.empty()) self->write_next();
    });
  }

  FoxgloveServer::Impl& server_;
  websocket::stream<beast::tcp_stream> ws_;
  beast::flat_buffer buffer_, in_;
  http::request<http::string_body> request_;
  bool open_ = false;
  bool closing_ = false;
  std::deque<Outgoing> queue_;
  std::size_t queued_bytes_ = 0;
  std::size_t queued_replies_ = 0;
  std::chrono::steady_clock::time_point connected_at_, last_progress_;
  std::unordered_map<std::uint32_t, std::uint32_t> subscriptions_;  // subscription id -> channel
};

void FoxgloveServer::Impl::accept() {
  acceptor.async_accept([this](beast::error_code ec, tcp::socket socket) {
    if (ec) {
      if (!stopped) accept();
      return;
    }
    if (static_cast<int>(viewers.size()) >= options.max_clients && !evict_idle_viewer()) {
      counters.refused.fetch_add(1, std::memory_order_relaxed);
      beast::error_code ignored;
      socket.shutdown(tcp::socket::shutdown_both, ignored);
      socket.close(ignored);
    } else {
      viewers.push_back(std::make_shared<Viewer>(*this, std::move(socket)));
      counters.clients.store(viewers.size(), std::memory_order_relaxed);
      viewers.back()->start();
    }
    accept();
  });
}

bool FoxgloveServer::Impl::evict_idle_viewer() {
  const auto now = std::chrono::steady_clock::now();
  Viewer* longest = nullptr;
  std::chrono::steady_clock::duration idle{};
  for (const auto& v : viewers)
    if (const auto d = v->idle_for(now); d && *d > options.idle_grace && *d > idle) {
      idle = *d;
      longest = v.get();
    }
  if (longest == nullptr) return false;
  longest->disconnect();  // its slot is free once its read fails
  return true;
}

void FoxgloveServer::Impl::remove(const Viewer* viewer) {
  const auto it = std::find_if(viewers.begin(), viewers.end(), [&](const auto& v) { return v.get() == viewer; });
  if (it != viewers.end()) viewers.erase(it);
  counters.clients.store(viewers.size(), std::memory_order_relaxed);
}

void FoxgloveServer::Impl::tick() {
  if (stopped) return;
  const auto checked = std::chrono::steady_clock::now();
  for (const auto& v : viewers) v->check(checked);  // disconnects only: removal comes with the failed read
  if (on_tick && !viewers.empty()) {
    try {  // a tick that fails (memory) loses this tick's messages, not the next ticks
      on_tick();
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

FoxgloveServer::FoxgloveServer(FoxgloveServerOptions options, std::vector<Channel> channels)
    : impl_(std::make_shared<Impl>(std::move(options), std::move(channels))) {
  Impl& s = *impl_;
  const std::string where = s.options.address + ":" + std::to_string(s.options.port);
  beast::error_code ec;
  const asio::ip::address address = asio::ip::make_address(s.options.address, ec);
  if (ec) throw std::runtime_error("live view: '" + s.options.address + "' is not an IP address");
  const tcp::endpoint endpoint(address, static_cast<unsigned short>(s.options.port));
  s.acceptor.open(endpoint.protocol(), ec);
  if (!ec) s.acceptor.set_option(asio::socket_base::reuse_address(true), ec);
  if (!ec) s.acceptor.bind(endpoint, ec);
  if (!ec) s.acceptor.listen(asio::socket_base::max_listen_connections, ec);
  if (ec) throw std::runtime_error("live view: cannot listen on " + where + ": " + ec.message());
  s.server_info =
      server_info_message(s.options.name, std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(
                                                             std::chrono::system_clock::now().time_since_epoch())
                                                             .count()));
  s.advertise = advertise_message(s.channels);
}

FoxgloveServer::~FoxgloveServer() { stop(); }

int FoxgloveServer::port() const noexcept {
  beast::error_code ec;
  const tcp::endpoint e = impl_->acceptor.local_endpoint(ec);
  return ec ? -1 : e.port();
}

const FoxgloveServerCounters& FoxgloveServer::counters() const noexcept { return impl_->counters; }

void FoxgloveServer::start(std::chrono::nanoseconds period, std::function<void()> on_tick) {
  Impl& s = *impl_;
  s.period = period;
  s.on_tick = std::move(on_tick);
  s.next_tick = std::chrono::steady_clock::now();
  s.accept();
  s.tick();
  s.thread = std::thread([&s] {
    // A handler that throws (memory) loses its viewer's message or request, never the thread: it runs on.
    for (;;) {
      try {
        s.io.run();
        return;
      } catch (...) {
        s.counters.bad_requests.fetch_add(1, std::memory_order_relaxed);
      }
    }
  });
}

void FoxgloveServer::stop() {
  Impl& s = *impl_;
  if (s.thread.joinable()) {
    asio::post(s.io, [&s] {
      s.stopped = true;
      beast::error_code ignored;
      s.acceptor.close(ignored);
      s.timer.cancel();
      for (const auto& v : s.viewers) v->close();
      s.viewers.clear();
      s.io.stop();
    });
    s.thread.join();
  }
  s.counters.clients.store(0, std::memory_order_relaxed);
}

bool FoxgloveServer::subscribed(std::uint32_t channel) const noexcept {
  return std::any_of(impl_->viewers.begin(), impl_->viewers.end(),
                     [&](const auto& v) { return v->subscribed(channel); });
}

void FoxgloveServer::publish(std::uint32_t channel, std::uint64_t time_ns, std::string_view payload) {
  Impl& s = *impl_;
  for (const auto& v : s.viewers) {  // send() only queues: a failed write removes its viewer later, not here
    v->for_each_subscription(channel, [&](std::uint32_t subscription) {
      message_data(s.frame, subscription, time_ns, payload);
      v->send(std::make_shared<const std::string>(s.frame), true);
    });
  }
}

}  // namespace hapticd::server::live_view
