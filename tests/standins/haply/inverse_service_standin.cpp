#include "inverse_service_standin.hpp"

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core/buffers_to_string.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <thread>

#include "hand_trigger.hpp"

namespace hapticd::standins {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = net::ip::tcp;
using Clock = std::chrono::steady_clock;

struct InverseServiceStandIn::Impl {
  Options options;
  net::io_context io;
  tcp::acceptor acceptor{io};
  std::thread thread;
  std::atomic<bool> stopping{false};
  mutable std::mutex mutex;  // the physics and the controls
  std::array<double, 3> p{0.0, -0.12, 0.15}, v{0, 0, 0}, f{0, 0, 0}, hand{0, 0, 0};
  std::array<double, 3> lo{-0.15, -0.25, 0.0}, hi{0.15, 0.0, 0.3};
  double mass_kg = 0.2, damping = 1.0, wall_stiffness = 3000.0;
  unsigned buttons = 0;
  bool unplugged = false;
  Clock::time_point pause_until{};
  Clock::time_point last{};
  std::atomic<std::uint64_t> messages{0};
  std::atomic<int> socket_fd{-1};
  std::string call_log;  // the lifecycle as the service saw it (under mutex)

  // Logs an event, a repeat of the last one once (a run of forces is one line).
  void log(const std::string& event) {
    std::lock_guard lock(mutex);
    const std::string line = event + "\n";
    if (call_log.size() >= line.size() && call_log.compare(call_log.size() - line.size(), line.size(), line) == 0)
      return;
    call_log += line;
  }

  HandTrigger hand_trigger;

  void step(double dt) {
    const bool pushing = hand_trigger.pushing();
    for (std::size_t i = 0; i < 3; ++i) {
      double wall = 0.0;
      if (p[i] > hi[i]) wall = -wall_stiffness * (p[i] - hi[i]);
      if (p[i] < lo[i]) wall = -wall_stiffness * (p[i] - lo[i]);
      const double a = (f[i] + (pushing ? hand[i] : 0.0) + wall - damping * v[i]) / mass_kg;
      v[i] += a * dt;
      p[i] += v[i] * dt;
    }
  }

  std::string state_json(bool inventory) {
    std::lock_guard lock(mutex);
    char cursor[512];
    std::snprintf(cursor, sizeof cursor,
                  "\"state\":{\"cursor_position\":{\"x\":%.9f,\"y\":%.9f,\"z\":%.9f},\"cursor_velocity\":{\"x\":%.9f,"
                  "\"y\":%.9f,\"z\":%.9f},\"current_cursor_force\":{\"x\":%.6f,\"y\":%.6f,\"z\":%.6f},"
                  "\"control_mode\":\"%s\"},\"status\":{\"calibrated\":%s,\"in_use\":true,\"power_supply\":true,"
                  "\"ready\":true,\"started\":true}",
                  p[0], p[1], p[2], v[0], v[1], v[2], f[0], f[1], f[2], "cartesian",
                  options.calibrated ? "true" : "false");
    std::string out = "{";
    if (inventory) out += "\"session_id\":7,";
    if (unplugged) {
      out += "\"inverse3\":[]}";
      return out;
    }
    out += "\"inverse3\":[{\"device_id\":\"" + options.device_id + "\",";
    if (inventory)
      out +=
          "\"config\":{\"type\":\"inverse3\",\"handedness\":\"right\",\"gravity_compensation\":{\"enabled\":true,"
          "\"scaling_factor\":1.0}},";
    out += cursor;
    out += "}]";
    if (!options.grip_id.empty()) {
      char grip[256];
      std::snprintf(grip, sizeof grip,
                    ",\"wireless_verse_grip\":[{\"device_id\":\"%s\",\"state\":{\"orientation\":{\"w\":0.7071068,"
                    "\"x\":0.0,\"y\":0.0,\"z\":0.7071068},\"buttons\":{\"a\":%s,\"b\":%s,\"c\":%s},"
                    "\"battery_level\":0.9}}]",
                    options.grip_id.c_str(), (buttons & 1) ? "true" : "false", (buttons & 2) ? "true" : "false",
                    (buttons & 4) ? "true" : "false");
      out += grip;
    }
    out += "}";
    return out;
  }

  // The force a message commands (set_cursor_force of our device), if it has one; the message in the log.
  void take_command(const std::string& text) {
    for (const char c : text)
      if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) {
        log("non-text bytes");
        break;
      }
    if (text.find("\"session\":{\"configure\":{\"profile\"") != std::string::npos) log("session profile");
    const std::size_t at = text.find("\"set_cursor_force\"");
    if (at == std::string::npos || text.find("\"" + options.device_id + "\"") == std::string::npos) {
      log("other message");
      return;
    }
    double x = 0, y = 0, z = 0;
    const char* vector = std::strstr(text.c_str() + at, "\"vector\"");
    if (vector == nullptr || std::sscanf(vector, "\"vector\":{\"x\":%lf,\"y\":%lf,\"z\":%lf", &x, &y, &z) != 3) {
      log("malformed set_cursor_force");
      return;
    }
    log(x == 0.0 && y == 0.0 && z == 0.0 ? "set_cursor_force zero" : "set_cursor_force");
    std::lock_guard lock(mutex);
    f = {x, y, z};
  }

  void serve(tcp::socket socket) {
    socket_fd.store(socket.native_handle());
    websocket::stream<tcp::socket> ws(std::move(socket));
    beast::error_code ec;
    ws.accept(ec);
    if (ec) return;
    log("connect");
    ws.text(true);
    {
      std::lock_guard lock(mutex);
      last = Clock::now();
    }
    if (options.send_inventory) {
      ws.write(net::buffer(state_json(true)), ec);
      log("inventory");
    }
    if (options.ignore_close) {
      // Beast answers a close frame once this callback returns: it returns when the stand-in ends.
      ws.control_callback([this](websocket::frame_type kind, beast::string_view) {
        if (kind != websocket::frame_type::close) return;
        log("close ignored");
        while (!stopping.load()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
      });
    }
    beast::flat_buffer buffer;
    while (!ec && !stopping.load()) {
      buffer.clear();
      ws.read(buffer, ec);
      if (ec) break;
      take_command(beast::buffers_to_string(buffer.cdata()));
      if (!options.send_inventory) continue;  // a service that never got going
      for (;;) {                              // paused: no answer until it ends
        Clock::time_point until;
        {
          std::lock_guard lock(mutex);
          until = pause_until;
        }
        if (Clock::now() >= until || stopping.load()) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
      {
        std::lock_guard lock(mutex);
        const Clock::time_point now = Clock::now();
        double dt = options.step_s > 0.0 ? options.step_s : std::chrono::duration<double>(now - last).count();
        last = now;
        for (; dt > 1e-9; dt -= 0.0002) step(std::min(dt, 0.0002));  // the physics in 0.2 ms steps
      }
      messages.fetch_add(1);
      ws.write(net::buffer(state_json(false)), ec);
    }
    log(ec == websocket::error::closed ? "close" : "connection lost");
    socket_fd.store(-1);
  }
};

InverseServiceStandIn::InverseServiceStandIn(Options options) : impl_(std::make_unique<Impl>()) {
  impl_->options = std::move(options);
  const tcp::endpoint endpoint(net::ip::make_address("127.0.0.1"), static_cast<unsigned short>(impl_->options.port));
  impl_->acceptor.open(endpoint.protocol());
  impl_->acceptor.set_option(net::socket_base::reuse_address(true));
  impl_->acceptor.bind(endpoint);
  impl_->acceptor.listen();
  impl_->thread = std::thread([this] {
    while (!impl_->stopping.load()) {
      beast::error_code ec;
      tcp::socket socket(impl_->io);
      impl_->acceptor.accept(socket, ec);
      if (ec) break;
      impl_->serve(std::move(socket));
    }
  });
}

InverseServiceStandIn::~InverseServiceStandIn() {
  impl_->stopping.store(true);
  beast::error_code ec;
  (void)::shutdown(impl_->acceptor.native_handle(), SHUT_RDWR);
  if (const int fd = impl_->socket_fd.load(); fd >= 0) (void)::shutdown(fd, SHUT_RDWR);
  if (impl_->thread.joinable()) impl_->thread.join();
  impl_->acceptor.close(ec);
}

int InverseServiceStandIn::port() const noexcept { return impl_->acceptor.local_endpoint().port(); }
std::string InverseServiceStandIn::url() const { return "ws://127.0.0.1:" + std::to_string(port()); }

void InverseServiceStandIn::hand(double fx, double fy, double fz, unsigned buttons) {
  std::lock_guard lock(impl_->mutex);
  impl_->hand = {fx, fy, fz};
  impl_->buttons = buttons;
}

void InverseServiceStandIn::pause(double seconds) {
  std::lock_guard lock(impl_->mutex);
  impl_->pause_until =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

void InverseServiceStandIn::unplug() {
  std::lock_guard lock(impl_->mutex);
  impl_->unplugged = true;
}

void InverseServiceStandIn::drop() {
  if (const int fd = impl_->socket_fd.load(); fd >= 0) (void)::shutdown(fd, SHUT_RDWR);
}

InverseServiceStandIn::Cursor InverseServiceStandIn::cursor() const {
  std::lock_guard lock(impl_->mutex);
  return Cursor{impl_->p, impl_->f};
}

std::uint64_t InverseServiceStandIn::messages() const noexcept { return impl_->messages.load(); }

std::string InverseServiceStandIn::call_log() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->call_log;
}

}  // namespace hapticd::standins
