#include "inverse_service_client.hpp"

#include <sys/socket.h>

#include <atomic>
#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <cmath>

namespace hapticd::plugins::haply {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = net::ip::tcp;

struct InverseServiceClient::Impl {
  net::io_context io;
  websocket::stream<tcp::socket> ws{io};
  beast::flat_buffer buffer;
  std::atomic<int> fd{-1};

  // Runs the asynchronous operation `start` begins (it calls its handler with an error code) until it completes or
  // `timeout_s` passes; a late one is cancelled (its handler still runs: the stream is left in no half state).
  // The operation's error, or timed_out.
  template <class Start>
  beast::error_code run(double timeout_s, Start&& start) {
    beast::error_code result;
    bool done = false;
    io.restart();
    start([&](beast::error_code ec, auto&&...) {
      result = ec;
      done = true;
    });
    const double bounded = std::isfinite(timeout_s) && timeout_s > 0.0 ? std::min(timeout_s, 3600.0) : 0.0;
    io.run_for(std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(bounded)));
    if (done) return result;
    beast::error_code ignored;
    (void)ws.next_layer().cancel(ignored);
    io.restart();
    io.run();  // the cancelled handler
    return beast::error::timeout;
  }
};

std::string InverseServiceClient::check_url(const std::string& url) {
  const std::string scheme = "ws://";
  if (url.rfind(scheme, 0) != 0) return "'" + url + "' is not a ws:// URL (the Inverse Service's simulation channel)";
  const std::string authority = url.substr(scheme.size(), url.find('/', scheme.size()) - scheme.size());
  const std::size_t colon = authority.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == authority.size())
    return "'" + url + "' names no host and port (ws://127.0.0.1:10001)";
  return "";
}

InverseServiceClient::InverseServiceClient(const std::string& url) : impl_(std::make_unique<Impl>()), url_(url) {
  const std::string rest = url.substr(std::string("ws://").size());
  const std::size_t slash = rest.find('/');
  const std::string authority = rest.substr(0, slash);
  path_ = slash == std::string::npos ? "/" : rest.substr(slash);
  const std::size_t colon = authority.rfind(':');
  host_ = authority.substr(0, colon);
  port_ = authority.substr(colon + 1);
  impl_->ws.read_message_max(kMaxMessageBytes);
  impl_->buffer.reserve(1 << 16);
}

InverseServiceClient::~InverseServiceClient() { close(); }

std::string InverseServiceClient::connect(double timeout_s) {
  beast::error_code ec;
  tcp::resolver resolver(impl_->io);
  const auto endpoints = resolver.resolve(host_, port_, ec);  // numeric or /etc/hosts: the service is local
  tcp::socket& socket = impl_->ws.next_layer();
  if (!ec && endpoints.empty()) ec = net::error::host_not_found;
  if (!ec) (void)socket.open(endpoints.begin()->endpoint().protocol(), ec);
  if (!ec) {
    impl_->fd.store(socket.native_handle());
    const auto started = std::chrono::steady_clock::now();
    ec = impl_->run(timeout_s, [&](auto handler) { net::async_connect(socket, endpoints, handler); });
    if (!ec) (void)socket.set_option(tcp::no_delay(true), ec);
    const double left = timeout_s - std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    if (!ec)
      ec = impl_->run(std::max(left, 1e-3), [&](auto handler) { impl_->ws.async_handshake(host_, path_, handler); });
  }
  if (ec == beast::error::timeout)
    return "cannot connect to the Inverse Service at " + url_ + ": no answer within connect_timeout_s";
  if (ec) return "cannot connect to the Inverse Service at " + url_ + ": " + ec.message();
  impl_->ws.text(true);
  return "";
}

bool InverseServiceClient::send(std::string_view text, double timeout_s) noexcept {
  const beast::error_code ec = impl_->run(
      timeout_s, [&](auto handler) { impl_->ws.async_write(net::buffer(text.data(), text.size()), handler); });
  if (ec) error_ = ec == beast::error::timeout ? "the service took no message within the time allowed" : ec.message();
  return !ec;
}

bool InverseServiceClient::receive(std::string_view& text, double timeout_s) noexcept {
  impl_->buffer.clear();
  const beast::error_code ec =
      impl_->run(timeout_s, [&](auto handler) { impl_->ws.async_read(impl_->buffer, handler); });
  if (ec) {
    if (ec == websocket::error::closed)
      error_ = "the service closed the connection";
    else if (ec == beast::error::timeout)
      error_ = "the service sent nothing within the time allowed";
    else if (ec == websocket::error::message_too_big || ec == websocket::error::buffer_overflow)
      error_ = "the service sent a message larger than " + std::to_string(kMaxMessageBytes / 1024) + " KiB";
    else
      error_ = ec.message();
    return false;
  }
  const auto data = impl_->buffer.cdata();
  text = std::string_view(static_cast<const char*>(data.data()), data.size());
  return true;
}

void InverseServiceClient::close() noexcept {
  if (!impl_) return;
  if (const int fd = impl_->fd.load(); fd >= 0) (void)::shutdown(fd, SHUT_RDWR);
}

void InverseServiceClient::close_gracefully(double timeout_s) noexcept {
  if (!impl_ || impl_->fd.load() < 0) return;
  if (impl_->ws.is_open())  // reads (and drops) what is still in flight, then the service's close
    (void)impl_->run(timeout_s, [&](auto handler) { impl_->ws.async_close(websocket::close_code::normal, handler); });
  close();
}

}  // namespace hapticd::plugins::haply
