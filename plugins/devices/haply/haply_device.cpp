#include "haply_device.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <stdexcept>

namespace hapticd::plugins::haply {
namespace {

std::int64_t now_ns() { return realtime::TickSignal::now_ns(); }

void sleep_until(std::int64_t t) {
  timespec ts{static_cast<time_t>(t / 1'000'000'000), static_cast<long>(t % 1'000'000'000)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

// The device entry of `kind` with `id` in a state message ("" the first), or none.
JsonReader::Value device_entry(const JsonReader::Value& root, std::string_view kind, std::string_view id) {
  const JsonReader::Value list = root[kind];
  for (std::size_t i = 0; i < list.size(); ++i) {
    const JsonReader::Value d = list.at(i);
    if (id.empty() || d["device_id"].string() == id) return d;
  }
  return {};
}

bool vec3(const JsonReader::Value& v, std::array<double, 3>& out) {
  const auto x = v["x"].number(), y = v["y"].number(), z = v["z"].number();
  if (!x || !y || !z || !std::isfinite(*x) || !std::isfinite(*y) || !std::isfinite(*z)) return false;
  out = {*x, *y, *z};
  return true;
}

// Why a device id from the inventory cannot be used ("" when it can): it is written into every command, so it is
// short and plain (Haply's ids are a few hex digits).
std::string id_problem(std::string_view id) {
  const auto plain = [](char c) {
    return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '-' || c == '_' ||
           c == '.';
  };
  if (id.empty()) return "is empty";
  if (id.size() > HaplyDevice::kMaxIdLength)
    return "has " + std::to_string(id.size()) + " characters (at most " + std::to_string(HaplyDevice::kMaxIdLength) +
           ")";
  for (const char c : id)
    if (!plain(c)) return "has a character other than letters, digits, '-', '_' and '.'";
  return "";
}

// The first characters of an id for a message.
std::string shown(std::string_view id) { return std::string(id.substr(0, 24)) + (id.size() > 24 ? "..." : ""); }

}  // namespace

ParameterSchema HaplyDevice::parameter_schema() {
  ParameterSchema s;
  s.string("url", "the Inverse Service's simulation channel").default_value("ws://127.0.0.1:10001");
  s.string("device_id", "the Inverse3's device_id (on its label and in Haply Hub); empty: the first").default_value("");
  s.string("grip", "the VerseGrip whose orientation and buttons the handle has: auto (the first), none, or its id")
      .default_value("auto");
  s.real("max_force_n", "the largest force to command").unit("N").greater_than(0.0).maximum(10.0).default_value(3.0);
  s.real_vector("workspace_min", "the reachable box's lower corner in the device's frame")
      .unit("m")
      .size(3)
      .default_value(std::vector<double>{-0.15, -0.25, 0.0});
  s.real_vector("workspace_max", "the reachable box's upper corner")
      .unit("m")
      .size(3)
      .default_value(std::vector<double>{0.15, 0.0, 0.3});
  s.real("recommended_stiffness_n_per_m", "the largest stiffness to render (walls, position loops)")
      .unit("N/m")
      .greater_than(0.0)
      .default_value(1500.0);
  s.real("recommended_damping_n_s_per_m", "the largest damping to render")
      .unit("N s/m")
      .minimum(0.0)
      .default_value(5.0);
  s.boolean("require_calibrated", "refuse an Inverse3 whose status says it is not calibrated").default_value(true);
  s.real("connect_timeout_s", "connecting, the service's first message, and each answer after it")
      .unit("s")
      .greater_than(0.0)
      .maximum(30.0)
      .default_value(2.0);
  ServoHandoff<HaplySample, HaplyCommand>::add_parameters(s);
  return s;
}

HaplyDevice::~HaplyDevice() { stop(); }

void HaplyDevice::configure(const Parameters& p, const PluginContext& context) {
  const std::string url = p.string("url");
  if (std::string why = InverseServiceClient::check_url(url); !why.empty()) throw std::runtime_error(why);
  client_ = std::make_unique<InverseServiceClient>(url);
  const double timeout = p.real("connect_timeout_s");
  if (std::string why = client_->connect(timeout); !why.empty()) throw DeviceUnavailable(why);
  std::string_view text;
  if (!client_->receive(text, timeout))
    throw std::runtime_error("the Inverse Service at " + client_->url() +
                             " sent no device inventory: " + client_->error());
  if (!json_.parse(text))
    throw std::runtime_error("the Inverse Service's inventory is not JSON: " + std::string(json_.error()));
  const JsonReader::Value root = json_.root();
  const std::string wanted = p.string("device_id");
  const JsonReader::Value device = device_entry(root, "inverse3", wanted);
  if (!device)
    throw DeviceUnavailable(wanted.empty() ? "the Inverse Service at " + client_->url() + " reports no Inverse3"
                                           : "the Inverse Service reports no Inverse3 '" + wanted + "' (" +
                                                 std::to_string(root["inverse3"].size()) + " connected)");
  device_id_ = std::string(device["device_id"].string().value_or(""));
  if (std::string why = id_problem(device_id_); !why.empty())
    throw DeviceUnavailable("the Inverse Service at " + client_->url() + " reports an Inverse3 whose device_id ('" +
                            shown(device_id_) + "') " + why + ": not a device this plugin drives");
  const JsonReader::Value status = device["status"];
  if (status["ready"].boolean() == false)
    throw std::runtime_error("the Inverse3 '" + device_id_ + "' is not ready (the service's status: ready false)");
  if (p.boolean("require_calibrated") && status["calibrated"].boolean() == false)
    throw std::runtime_error("the Inverse3 '" + device_id_ +
                             "' is not calibrated (the service's status: calibrated false): calibrate it as Haply Hub "
                             "shows, or set require_calibrated: false");

  const std::string grip = p.string("grip");
  grip_id_.clear();
  grip_kind_.clear();
  if (grip != "none") {
    for (const char* kind : {"wireless_verse_grip", "verse_grip"}) {
      const JsonReader::Value g = device_entry(root, kind, grip == "auto" ? std::string_view() : grip);
      if (g) {
        grip_id_ = std::string(g["device_id"].string().value_or(""));
        if (std::string why = id_problem(grip_id_); !why.empty())
          throw DeviceUnavailable("the Inverse Service reports a VerseGrip whose device_id ('" + shown(grip_id_) +
                                  "') " + why + " (grip: none runs without it)");
        grip_kind_ = kind;
        break;
      }
    }
    if (grip_id_.empty() && grip != "auto")
      throw ParameterError("grip", "the Inverse Service reports no VerseGrip '" + grip + "'");
  }

  handoff_.configure(p, context.rate_hz);
  timeout_s_ = timeout;

  DeviceDescription& d = description_;
  d.model = "haply inverse3 " + device_id_ + (grip_id_.empty() ? "" : " with " + grip_kind_ + " " + grip_id_);
  d.serial = device_id_;  // the service's id of the Inverse3 (its serial as the service reports it)
  d.vendor_software = "Haply Inverse Service at " + url;
  d.interface = DeviceInterface::handle;
  HandleDescription& h = d.handle;
  h.senses_orientation = !grip_id_.empty();
  h.buttons = grip_kind_ == "wireless_verse_grip" ? 3 : grip_kind_.empty() ? 0 : 1;
  const std::vector<double> lo = p.real_vector("workspace_min"), hi = p.real_vector("workspace_max");
  h.workspace_min = Eigen::Vector3d(lo[0], lo[1], lo[2]);
  h.workspace_max = Eigen::Vector3d(hi[0], hi[1], hi[2]);
  if ((h.workspace_max - h.workspace_min).minCoeff() <= 0.0)
    throw ParameterError("workspace_max", "not above workspace_min on every axis");
  h.max_force_n = p.real("max_force_n");
  h.recommended_stiffness_n_per_m = p.real("recommended_stiffness_n_per_m");
  h.recommended_damping_n_s_per_m = p.real("recommended_damping_n_s_per_m");
}

bool HaplyDevice::take_state(std::string_view text, HaplySample& s) noexcept {
  if (!json_.parse(text)) {
    s.error = "a message from the Inverse Service is not JSON";
    return false;
  }
  const JsonReader::Value root = json_.root();
  const JsonReader::Value device = device_entry(root, "inverse3", device_id_);
  const JsonReader::Value state = device["state"];
  if (!vec3(state["cursor_position"], s.position) || !vec3(state["cursor_velocity"], s.velocity)) {
    s.error = device ? "the Inverse Service's state has no cursor position and velocity"
                     : "the Inverse Service's state no longer has the Inverse3 (unplugged?)";
    return false;
  }
  if (!grip_id_.empty()) {
    const JsonReader::Value grip = device_entry(root, grip_kind_, grip_id_)["state"];
    const JsonReader::Value q = grip["orientation"];
    const auto w = q["w"].number(), x = q["x"].number(), y = q["y"].number(), z = q["z"].number();
    if (w && x && y && z && std::isfinite(*w + *x + *y + *z)) s.orientation = {*w, *x, *y, *z};
    const JsonReader::Value buttons = grip["buttons"];
    s.buttons = 0;
    if (buttons) {
      if (buttons["a"].boolean().value_or(false)) s.buttons |= 0x1;
      if (buttons["b"].boolean().value_or(false)) s.buttons |= 0x2;
      if (buttons["c"].boolean().value_or(false)) s.buttons |= 0x4;
    } else if (grip["button"].boolean().value_or(false)) {
      s.buttons = 0x1;
    }
  }
  return true;
}

Outcome HaplyDevice::enable() {
  if (!client_) return Outcome::failure("the Inverse Service is not connected");
  if (running_.exchange(true)) return Outcome::success();
  have_sample_ = false;
  handoff_.reset();
  io_done_.store(false);
  const std::uint64_t before = handoff_.samples();
  io_ = std::thread([this] {
    run();
    io_done_.store(true);
  });
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(1);
  while (handoff_.samples() == before && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  if (handoff_.samples() == before) return Outcome::failure("the Inverse Service answered no message within 1 s");
  return Outcome::success();
}

void HaplyDevice::run() noexcept {
  char message[512];
  HaplyCommand applied;
  bool first = true;
  std::int64_t next_send = now_ns();
  while (running_.load(std::memory_order_acquire)) {
    // The force of this tick, in the shape of Haply's set_cursor_force; the first message registers the session.
    const int n = std::snprintf(
        message, sizeof message,
        "{%s\"inverse3\":[{\"device_id\":\"%s\",\"commands\":{\"set_cursor_force\":{\"vector\":{\"x\":%.6f,\"y\":%.6f,"
        "\"z\":%.6f}}}}]}",
        first ? "\"session\":{\"configure\":{\"profile\":{\"name\":\"hapticd\"}}}," : "", device_id_.c_str(),
        applied.force_n[0], applied.force_n[1], applied.force_n[2]);
    first = false;
    HaplySample s;
    if (n <= 0 || static_cast<std::size_t>(n) >= sizeof message) {  // the ids are checked: not expected
      s.error = "a command for the Inverse Service does not fit its buffer: nothing is sent";
      s.received_ns = now_ns();
      handoff_.publish(s, s.received_ns);
      break;
    }
    // Paced at the session's rate: the service answers as fast as it is asked.
    sleep_until(next_send);
    next_send = std::max(next_send + handoff_.period_ns(), now_ns() - handoff_.period_ns());
    std::string_view text;
    if (!client_->send(std::string_view(message, static_cast<std::size_t>(n)), timeout_s_) ||
        !client_->receive(text, timeout_s_)) {
      if (!running_.load()) break;
      s.error =
          "the connection to the Inverse Service failed (the service stopped, closed it, did not answer within "
          "connect_timeout_s or sent a message over the size limit)";
      s.received_ns = now_ns();
      handoff_.publish(s, s.received_ns);
      break;
    }
    s.received_ns = now_ns();
    (void)take_state(text, s);
    handoff_.publish(s, s.received_ns);
    handoff_.next_command(applied);  // on the device's clock: the loop's answer to this state
  }
}

Outcome HaplyDevice::read(const CycleTime& cycle, DeviceState& state) {
  if (handoff_.take(sample_)) have_sample_ = true;
  if (!have_sample_) return Outcome::failure("no state from the Inverse Service yet");
  if (sample_.error != nullptr) return Outcome::failure(sample_.error);
  if (now_ns() - sample_.received_ns > handoff_.max_sample_age_ns())
    return Outcome::failure("no state from the Inverse Service within max_sample_age_s (it stopped answering)");
  HandleState& h = state.handle;
  state.timestamp_ns = cycle.time_ns;
  h.pose.position = Eigen::Vector3d(sample_.position[0], sample_.position[1], sample_.position[2]);
  h.twist.linear = Eigen::Vector3d(sample_.velocity[0], sample_.velocity[1], sample_.velocity[2]);
  if (description_.handle.senses_orientation)
    h.pose.orientation = Eigen::Quaterniond(sample_.orientation[0], sample_.orientation[1], sample_.orientation[2],
                                            sample_.orientation[3])
                             .normalized();
  h.buttons = sample_.buttons;
  return Outcome::success();
}

Outcome HaplyDevice::write_handle(const CycleTime&, const HandleCommand& command) {
  HaplyCommand c;  // (finite and bounded: the server's safety layer made it so)
  for (std::size_t i = 0; i < 3; ++i) c.force_n[i] = command.force_n[static_cast<Eigen::Index>(i)];
  handoff_.command(c);
  return Outcome::success();
}

void HaplyDevice::disable() { stop(); }

void HaplyDevice::stop() noexcept {
  const bool was_running = running_.exchange(false);
  if (io_.joinable()) {
    // The I/O thread ends after the exchange in progress (the service answers within a period); one that no longer
    // answers: the connection is closed under it.
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(50);
    while (!io_done_.load() && std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (!io_done_.load()) client_->close();
    io_.join();
  }
  if (client_ && was_running) {
    // The service's commands hold for one tick only (the device idles without them); a zero force all the same.
    char message[256];
    const int n = std::snprintf(message, sizeof message,
                                "{\"inverse3\":[{\"device_id\":\"%s\",\"commands\":{\"set_cursor_force\":{\"vector\":{"
                                "\"x\":0,\"y\":0,\"z\":0}}}}]}",
                                device_id_.c_str());
    if (n > 0 && static_cast<std::size_t>(n) < sizeof message &&
        client_->send(std::string_view(message, static_cast<std::size_t>(n)), 0.1)) {
      client_->close_gracefully(0.1);  // the service answers the force with a state, then the close
      return;
    }
  }
  if (client_) client_->close();
}

}  // namespace hapticd::plugins::haply
