#pragma once
// A stand-in for Haply's Inverse Service, built by the project for its tests from the service's published
// simulation-channel protocol (docs.haply.co, Inverse Service 3.x: on connecting, an inventory of every device with
// config, state and status; then exactly one state message for each message received; set_cursor_force under a
// device's "commands"). Loopback only (127.0.0.1). Behind it: an Inverse3 cursor with mass and damping in a
// walled box, a simulated hand pushing it, and a wireless VerseGrip with orientation and buttons; and controls for
// the tests: the hand, a pause (the service answers nothing), a dropped connection. None of Haply's code.
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

namespace hapticd::standins {

class InverseServiceStandIn {
 public:
  struct Options {
    int port = 0;  // 0: any free port (port() tells)
    std::string device_id = "049D";
    std::string grip_id = "61548";  // "": no VerseGrip
    bool calibrated = true;
    // Each message advances the physics by this much (a service in step with its client, so a loaded test machine
    // does not change the run); 0: by the time since the previous message.
    double step_s = 0.001;
    // Hostile or broken services (hardening, docs/safety.md): no inventory after the handshake (the service waits);
    // the client's close frame never read nor answered (every message before it is; the connection stays open
    // until the stand-in ends).
    bool send_inventory = true;
    bool ignore_close = false;
  };
  explicit InverseServiceStandIn(Options options);
  ~InverseServiceStandIn();
  InverseServiceStandIn(const InverseServiceStandIn&) = delete;
  InverseServiceStandIn& operator=(const InverseServiceStandIn&) = delete;

  [[nodiscard]] int port() const noexcept;
  [[nodiscard]] std::string url() const;
  // The hand pushes the cursor with this force [N]; the grip's buttons a, b, c as bits 0, 1, 2.
  void hand(double fx, double fy, double fz, unsigned buttons);
  // Answers nothing for this long (a service that stopped).
  void pause(double seconds);
  // Closes the connection now.
  void drop();
  // The Inverse3 is unplugged: the service's states no longer list it (the connection stays).
  void unplug();
  struct Cursor {
    std::array<double, 3> position{}, force{};  // m, N: the last force commanded
  };
  [[nodiscard]] Cursor cursor() const;
  [[nodiscard]] std::uint64_t messages() const noexcept;
  // The lifecycle as the service saw it, one event per line, a run of the same event once: "connect",
  // "inventory", "session profile", "set_cursor_force" (or "... zero"), "close" (the client closed the WebSocket)
  // or "connection lost"; "non-text bytes" for a message with bytes that are not printable ASCII; "close ignored"
  // when ignore_close takes effect.
  [[nodiscard]] std::string call_log() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hapticd::standins
