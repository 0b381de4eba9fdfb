#include "live_view/foxglove_server.hpp"

#include <algorithm>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <deque>
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

}  // namespace

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
  [[nodiscard]] bool has_channel(std::uint32_t id) const {
    return std::any_of(channels.begin(), channels.end(), [&](const Channel& c) { return c.id == id; });
  }
};

// One connected viewer: the HTTP upgrade, then its messages in and out (one write at a time, a bounded queue).
class Viewer : public std::enable_shared_from_this<Viewer> {
 public:
  Viewer(FoxgloveServer::Impl& server, tcp::socket socket) : server_(server), ws_(std::move(socket)) {}

  void start() {
    beast::get_lowest_layer(ws_).expires_after(server_.options.handshake_timeout);
    http::async_read(beast::get_lowest_layer(ws_), buffer_, request_,
                     [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_request(ec); });
  }

  void close() {
    beast::error_code ignored;
    beast::get_lowest_layer(ws_).socket().shutdown(tcp::socket::shutdown_both, ignored);
    beast::get_lowest_layer(ws_).close();
  }

  // Queues a message; binary data is dropped (and counted) when the queue is full.
  void send(std::shared_ptr<const std::string> data, bool binary) {
    if (!open_) return;
    if (binary && queued_bytes_ + data->size() > server_.options.max_queued_bytes) {
      server_.counters.dropped.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    queued_bytes_ += data->size();
    queue_.push_back({std::move(data), binary});
    server_.counters.sent.fetch_add(1, std::memory_order_relaxed);
    if (queue_.size() == 1) write_next();
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

  void refuse(http::status status, std::string text) {
    auto response = std::make_shared<http::response<http::string_body>>(status, request_.version());
    response->set(http::field::content_type, "text/plain");
    response->body() = std::move(text);
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
        return reply_error(1, "'" + r.op + "' is not offered by this server (it offers subscribe and unsubscribe)");
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
      self->queue_.pop_front();
      if (ec) {
        self->open_ = false;
        self->queue_.clear();
        self->queued_bytes_ = 0;
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
  std::deque<Outgoing> queue_;
  std::size_t queued_bytes_ = 0;
  std::unordered_map<std::uint32_t, std::uint32_t> subscriptions_;  // subscription id -> channel
};

void FoxgloveServer::Impl::accept() {
  acceptor.async_accept([this](beast::error_code ec, tcp::socket socket) {
    if (ec) {
      if (!stopped) accept();
      return;
    }
    if (static_cast<int>(viewers.size()) >= options.max_clients) {
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

void FoxgloveServer::Impl::remove(const Viewer* viewer) {
  const auto it = std::find_if(viewers.begin(), viewers.end(), [&](const auto& v) { return v.get() == viewer; });
  if (it != viewers.end()) viewers.erase(it);
  counters.clients.store(viewers.size(), std::memory_order_relaxed);
}

void FoxgloveServer::Impl::tick() {
  if (stopped) return;
  if (on_tick && !viewers.empty()) on_tick();
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
  s.thread = std::thread([&s] { s.io.run(); });
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
