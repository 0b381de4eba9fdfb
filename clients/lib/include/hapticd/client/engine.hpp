#pragma once
// hapticd::client::Engine - what every rendering engine does around its physics (docs/engines.md, "The engine
// helper"): find its device or group, claim it, answer each state through one callback, keep or retake the claim,
// follow parameter changes, end on a stop, a lost claim, the session's end or a server that went away (or wait for
// the server to come back and claim again), release, and say why it ended. The engine writes only its physics: the
// answer callback fills one command per device.
//
//   hapticd::client::Client client({"my-engine"});
//   hapticd::client::Engine engine(client, {.name = "my-engine", .device = "vishard3"});
//   if (!engine.connect()) return 1;
//   const auto end = engine.run([&](std::span<const DeviceState* const> states, std::span<EngineCommand> out) {
//     out[0] = EngineCommand::force(my_wrench(*states[0]), 0);  // the helper sets the serial
//     return true;
//   });
//   return end.exit_code();
//
// Threading: the answer callback runs on the client's receive thread (as Client::on_state's), one state at a time;
// every other hook runs on the thread that called run(). stop() and stop_all() may be called from any thread, and
// stop_all() from a signal handler.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hapticd/client/client.hpp"

namespace hapticd::client {

struct EngineOptions {
  std::string name = "engine";  // the prefix of its messages
  std::string device;           // the device to claim; empty (and no group): the only device on the domain
  std::string group;            // or the group to claim: one answer per group state, one group command
  Timeout wait{10.0};           // for the device or group to appear and start, and for a server to come back
  Timeout server_timeout{3.0};  // no state for this long: the session ended or the server is gone
  // After the session ended or the server went: wait `wait` for states to come again, claim again and go on
  // (the engine's world stays as it is); false: end.
  bool wait_for_server = false;
  Timeout duration{0.0};                                 // end after this long (0: until a stop or the server's end)
  Timeout chores_period{std::chrono::milliseconds(20)};  // how often run() calls the chores hook
  // Where its messages go (error: a reason it cannot go on); default: standard output or error, with the prefix.
  std::function<void(bool error, std::string_view line)> say;
};

// Why run() ended.
enum class EngineEndReason : std::uint8_t {
  finished,       // the duration passed
  stopped,        // stop() or stop_all()
  session_ended,  // the server's session ended, or no state came for server_timeout (and none came back)
  no_device,      // connect(): the device or group did not appear or start
  claim_refused,  // another engine holds it, or a claim hook refused
  claim_lost,     // the server ended the claim and another engine took the device
  failed,         // the answer callback threw, or a chores hook ended the run
};

struct EngineEnd {
  EngineEndReason reason = EngineEndReason::finished;
  std::string message;  // what happened, as said
  // 0: finished, stopped or the session ended; 1: no device; 2: refused or failed; 3: the claim was lost.
  [[nodiscard]] HAPTICD_API int exit_code() const noexcept;
};

class HAPTICD_API Engine {
 public:
  // One command per state (the same order); true: send them (the engine sets each command's state serial).
  using Answer = std::function<bool(std::span<const DeviceState* const> states, std::span<EngineCommand> commands)>;
  // After each accepted claim, before the first state is answered (again: a retaken claim, or the server came
  // back): read the session's parameters, place the world at the hands. False ends the run (say why first).
  using ClaimHook = std::function<bool(bool again)>;
  // Every chores_period on run()'s thread (publish a world, print progress); false ends the run (say why first).
  using ChoresHook = std::function<bool()>;
  // A parameter of one of its devices was set (EventKind::parameter), on run()'s thread as soon as it came;
  // answered_then: answered() when the event arrived.
  using ParameterHook = std::function<void(const Event& event, std::uint64_t answered_then)>;

  Engine(Client& client, EngineOptions options);
  ~Engine() = default;
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  // Finds the device (or the group, or the only device on the domain) and waits until it started: its
  // description with the start pose. False: said why (run() then ends at once with no_device); devices() is empty.
  bool connect();
  [[nodiscard]] const std::vector<std::string>& devices() const noexcept { return devices_; }
  [[nodiscard]] const DeviceInfo& description(std::size_t index) const { return descriptions_.at(index); }
  [[nodiscard]] const std::string& target() const noexcept { return target_; }  // the device or group claimed

  // How its commands go out, on the receive thread (set before run()): by default Client::send (a device) or
  // Client::send_group (a group). The C API hands them to its sender thread instead (no allocation there).
  using Send = std::function<bool(std::string_view target, bool group, std::span<const DeviceCommand> commands)>;
  void send_through(Send send) { send_ = std::move(send); }

  void on_claim(ClaimHook hook) { on_claim_ = std::move(hook); }
  void on_chores(ChoresHook hook) { on_chores_ = std::move(hook); }
  void on_parameter(ParameterHook hook) { on_parameter_ = std::move(hook); }

  // Claims and answers until it ends (see EngineEndReason); then releases. Connects first if connect() was not
  // called. Call once. For its run it takes the client's state (or group-state) and event callbacks (a Client has
  // one of each) and clears them when it ends; it leaves them alone before and after.
  EngineEnd run(Answer answer);
  void stop() noexcept;
  static void stop_all() noexcept;  // every Engine of the process (async-signal-safe: for SIGINT and SIGTERM)

  [[nodiscard]] std::uint64_t answered() const noexcept { return answered_.load(std::memory_order_relaxed); }
  // Says a line with the engine's prefix (as the helper's own messages).
  void say(std::string_view line, bool error = false) const;

 private:
  void answer(std::span<const DeviceState* const> states, std::uint64_t serial);
  bool claim(bool again);
  [[nodiscard]] bool stop_requested() const noexcept;
  void hook();
  void unhook();

  Client& client_;
  EngineOptions options_;
  std::vector<std::string> devices_;
  std::vector<DeviceInfo> descriptions_;
  std::string target_;
  bool connected_ = false;
  ClaimHook on_claim_;
  ChoresHook on_chores_;
  ParameterHook on_parameter_;
  Answer answer_;
  Send send_;
  std::vector<EngineCommand> commands_;        // the receive thread's
  std::vector<DeviceCommand> group_commands_;  // the receive thread's
  std::atomic<std::uint64_t> last_serial_{0};  // the newest state answered (reset by a claim)
  std::atomic<bool> running_{false};           // answering (claimed and set up)
  std::atomic<bool> stop_{false};
  std::atomic<bool> session_ending_{false};  // a state said stopping or off
  std::atomic<std::uint64_t> answered_{0}, seen_{0};
  std::mutex mutex_;  // guards the two below; with wake_
  std::condition_variable wake_;
  std::string answer_error_;
  std::vector<std::pair<Event, std::uint64_t>> parameter_events_;
};

}  // namespace hapticd::client
