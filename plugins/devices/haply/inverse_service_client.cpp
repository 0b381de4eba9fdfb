#include "inverse_service_client.hpp"

#include <sys/socket.h>
#include <sys/time.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/websocket.hpp>

namespace hapticd::plugins::haply {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = net::ip::tcp;

struct InverseServiceClient::Impl {
  net::io_context io;
  websocket::stream<tcp::socket> ws{io};
  beast::flat_buffer buffer;
  int fd = -1;
};

namespace {

// Blocking socket calls time out after `seconds` (0: never).
void set_timeout(int fd, double seconds) {
  timeval tv{};
  tv.tv_sec = static_cast<time_t>(seconds);
  tv.tv_usec = static_cast<suseconds_t>((seconds - static_cast<double>(tv.tv_sec)) * 1e6);
  (void)setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  (void)setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
}

}  // namespace

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
  impl_->buffer.reserve(1 << 16);
}

InverseServiceClient::~InverseServiceClient() { close(); }

std::string InverseServiceClient::connect(double timeout_s) {
  beast::error_code ec;
  tcp::resolver resolver(impl_->io);
  const auto endpoints = resolver.resolve(host_, port_, ec);
  tcp::socket& socket = impl_->ws.next_layer();
  if (!ec && !endpoints.empty()) (void)socket.open(endpoints.begin()->endpoint().protocol(), ec);
  if (!ec) {
    impl_->fd = socket.native_handle();
    set_timeout(impl_->fd, timeout_s);
    net::connect(socket, endpoints, ec);
  }
  if (!ec) (void)socket.set_option(tcp::no_delay(true), ec);
  if (!ec) impl_->ws.handshake(host_, path_, ec);
  if (ec) return "cannot connect to the Inverse Service at " + url_ + ": " + ec.message();
  impl_->ws.text(true);
  return "";
}

bool InverseServiceClient::send(std::string_view text) noexcept {
  beast::error_code ec;
  impl_->ws.write(net::buffer(text.data(), text.size()), ec);
  if (ec) error_ = ec.message();
  return !ec;
}

bool InverseServiceClient::receive(std::string_view& text, double timeout_s) noexcept {
  if (impl_->fd >= 0) set_timeout(impl_->fd, timeout_s);
  impl_->buffer.clear();
  beast::error_code ec;
  impl_->ws.read(impl_->buffer, ec);
  if (ec) {
    error_ = ec == websocket::error::closed ? "the service closed the connection" : ec.message();
    return false;
  }
  const auto data = impl_->buffer.cdata();
  text = std::string_view(static_cast<const char*>(data.data()), data.size());
  return true;
}

void InverseServiceClient::close() noexcept {
  if (impl_ && impl_->fd >= 0) (void)::shutdown(impl_->fd, SHUT_RDWR);
}

void InverseServiceClient::close_gracefully(double timeout_s) noexcept {
  if (!impl_ || impl_->fd < 0) return;
  if (impl_->ws.is_open()) {
    set_timeout(impl_->fd, timeout_s);
    beast::error_code ec;
    impl_->ws.close(websocket::close_code::normal, ec);  // reads (and drops) what is still in flight
  }
  close();
}

}  // namespace hapticd::plugins::haply
