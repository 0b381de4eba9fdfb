#include "live_view/foxglove_server.hpp"

#include <algorithm>
#include <unordered_map>

namespace hapticd::server::live_view {

using net::ConnectionId;
using net::quoted;
using net::WebSocketServer;

// The protocol's side of each viewer: its subscriptions, and the answers to its requests.
class FoxgloveServer::Protocol final : public net::WebSocketHandler {
 public:
  Protocol(std::vector<Channel> channels, const std::string& name)
      : channels_(std::move(channels)),
        server_info_(std::make_shared<const std::string>(
            server_info_message(name, std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(
                                                         std::chrono::system_clock::now().time_since_epoch())
                                                         .count())))),
        advertise_(std::make_shared<const std::string>(advertise_message(channels_))) {}

  WebSocketServer* transport = nullptr;
  std::function<void()> on_tick;

  void opened(ConnectionId id) override {
    viewers_[id];
    transport->send(id, server_info_, false, WebSocketServer::Kind::reply);
    transport->send(id, advertise_, false, WebSocketServer::Kind::reply);
  }
  void closed(ConnectionId id) override { viewers_.erase(id); }
  [[nodiscard]] bool idle(ConnectionId id) const override {
    const auto it = viewers_.find(id);
    return it == viewers_.end() || it->second.empty();
  }
  void tick() override {
    if (on_tick) on_tick();
  }

  void received(ConnectionId id, std::string_view message, bool binary) override {
    if (binary)
      return reply_error(id, 1, "binary messages from viewers are not taken (this server offers no client publishing)");
    const ClientRequest r = parse_client_request(message);
    auto& subscriptions = viewers_[id];
    switch (r.kind) {
      case ClientRequest::Kind::invalid:
        return reply_error(id, 2, "request refused: " + r.error);
      case ClientRequest::Kind::unsupported:
        return reply_error(
            id, 1, "'" + quoted(r.op) + "' is not offered by this server (it offers subscribe and unsubscribe)");
      case ClientRequest::Kind::subscribe:
        for (const Subscription& s : r.subscriptions) {
          if (!has_channel(s.channel))
            reply_error(id, 2, "subscribe: no channel " + std::to_string(s.channel));
          else if (subscriptions.count(s.id) != 0)
            reply_error(id, 2, "subscribe: subscription id " + std::to_string(s.id) + " is in use");
          else if (subscriptions.size() >= 4 * channels_.size())
            reply_error(id, 2, "subscribe: too many subscriptions");
          else
            subscriptions.emplace(s.id, s.channel);
        }
        return;
      case ClientRequest::Kind::unsubscribe:
        for (const std::uint32_t s : r.subscription_ids) subscriptions.erase(s);
        return;
    }
  }

  [[nodiscard]] bool subscribed(std::uint32_t channel) const noexcept {
    return std::any_of(viewers_.begin(), viewers_.end(), [&](const auto& v) {
      return std::any_of(v.second.begin(), v.second.end(), [&](const auto& s) { return s.second == channel; });
    });
  }

  void publish(std::uint32_t channel, std::uint64_t time_ns, std::string_view payload) {
    for (const auto& [id, subscriptions] : viewers_)
      for (const auto& [subscription, ch] : subscriptions)
        if (ch == channel) {
          message_data(frame_, subscription, time_ns, payload);
          transport->send(id, std::make_shared<const std::string>(frame_), true, WebSocketServer::Kind::data);
        }
  }

 private:
  void reply_error(ConnectionId id, int level, const std::string& text) {
    transport->send(id, std::make_shared<const std::string>(status_message(level, text)), false,
                    WebSocketServer::Kind::reply);
    transport->count_bad_request();
  }
  [[nodiscard]] bool has_channel(std::uint32_t id) const {
    return std::any_of(channels_.begin(), channels_.end(), [&](const Channel& c) { return c.id == id; });
  }

  std::vector<Channel> channels_;
  std::shared_ptr<const std::string> server_info_, advertise_;
  std::unordered_map<ConnectionId, std::unordered_map<std::uint32_t, std::uint32_t>> viewers_;  // id -> channel
  std::string frame_;  // reused for each message's binary frame
};

FoxgloveServer::FoxgloveServer(FoxgloveServerOptions options, std::vector<Channel> channels)
    : protocol_(std::make_unique<Protocol>(std::move(channels), options.name)) {
  net::WebSocketOptions o;
  o.what = "live view";
  o.address = options.address;
  o.port = options.port;
  o.max_clients = options.max_clients;
  o.server_header = "hapticd live view";
  o.subprotocol = std::string(kSubprotocol);
  o.subprotocol_hint = "hapticd's live view speaks the Foxglove WebSocket protocol: connect with the subprotocol " +
                       std::string(kSubprotocol) + " (Foxglove or Lichtblick: Open connection, Foxglove WebSocket)";
  o.max_queued_bytes = options.max_queued_bytes;
  o.max_queued_replies = options.max_queued_replies;
  o.max_message_bytes = kMaxClientMessageBytes;
  o.slow_timeout = options.slow_viewer_timeout;
  o.idle_timeout = options.idle_timeout;
  o.idle_grace = options.idle_grace;
  o.handshake_timeout = options.handshake_timeout;
  o.allowed_origins = options.allowed_origins;
  o.origin_hint = "the origins listed in the session's live_view.allowed_origins";
  if (!options.page.empty()) o.pages.push_back({"/viewer.html", options.page});
  transport_ = std::make_unique<WebSocketServer>(std::move(o), *protocol_);
  protocol_->transport = transport_.get();
}

FoxgloveServer::~FoxgloveServer() { stop(); }

int FoxgloveServer::port() const noexcept { return transport_->port(); }

const FoxgloveServerCounters& FoxgloveServer::counters() const noexcept { return transport_->counters(); }

void FoxgloveServer::start(std::chrono::nanoseconds period, std::function<void()> on_tick) {
  protocol_->on_tick = std::move(on_tick);
  transport_->start(period);
}

void FoxgloveServer::stop() { transport_->stop(); }

bool FoxgloveServer::subscribed(std::uint32_t channel) const noexcept { return protocol_->subscribed(channel); }

void FoxgloveServer::publish(std::uint32_t channel, std::uint64_t time_ns, std::string_view payload) {
  protocol_->publish(channel, time_ns, payload);
}

}  // namespace hapticd::server::live_view
