#include "hapticd/client/engine.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <exception>
#include <thread>

namespace hapticd::client {

namespace {

using Clock = std::chrono::steady_clock;

std::atomic<bool> g_stop_all{false};

std::string seconds_text(Timeout t) {
  std::array<char, 32> buffer{};
  (void)std::snprintf(buffer.data(), buffer.size(), "%g", t.count());
  return buffer.data();
}

std::string in_quotes(std::string_view name) { return "'" + std::string(name) + "'"; }

// The main loop's chores come every chores_period; a gap between two passes longer than this is the engine's own
// process standing still (stopped, swapped out), not the server's silence.
constexpr Timeout kOwnStall{0.5};
// After a state that said the session is ending, this much silence is its end.
constexpr Timeout kEndingSilence{0.2};

}  // namespace

int EngineEnd::exit_code() const noexcept {
  switch (reason) {
    case EngineEndReason::finished:
    case EngineEndReason::stopped:
    case EngineEndReason::session_ended:
      return 0;
    case EngineEndReason::no_device:
      return 1;
    case EngineEndReason::claim_lost:
      return 3;
    case EngineEndReason::claim_refused:
    case EngineEndReason::failed:
      break;
  }
  return 2;
}

Engine::Engine(Client& client, EngineOptions options) : client_(client), options_(std::move(options)) {
  target_ = options_.group.empty() ? options_.device : options_.group;
}

void Engine::say(std::string_view line, bool error) const {
  if (options_.say) {
    options_.say(error, line);
    return;
  }
  std::FILE* to = error ? stderr : stdout;
  std::fprintf(to, "%s: %.*s\n", options_.name.c_str(), static_cast<int>(line.size()), line.data());
  std::fflush(to);
}

bool Engine::stop_requested() const noexcept {
  return stop_.load(std::memory_order_acquire) || g_stop_all.load(std::memory_order_acquire);
}

void Engine::stop() noexcept {
  {
    std::lock_guard lock(mutex_);
    stop_.store(true, std::memory_order_release);
  }
  wake_.notify_all();
}

void Engine::stop_all() noexcept { g_stop_all.store(true, std::memory_order_release); }

bool Engine::connect() {
  if (connected_) return true;
  const std::string wait = seconds_text(options_.wait);
  if (!options_.group.empty()) {
    const auto g = client_.wait_for_group(options_.group, options_.wait);
    if (!g) {
      say("no group " + in_quotes(options_.group) + " within " + wait + " s", true);
      return false;
    }
    devices_ = g->devices;
  } else if (!options_.device.empty()) {
    devices_ = {options_.device};
  } else {
    const auto until = Clock::now() + options_.wait;
    while (client_.devices().empty() && Clock::now() < until && !stop_requested())
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const auto found = client_.devices();
    if (found.size() != 1) {
      say(std::to_string(found.size()) + " devices found: name one", true);
      return false;
    }
    devices_ = {found.front().device};
    target_ = devices_.front();
  }
  // Started: the description carries the start pose (an engine that restarts places its world by it again).
  for (const std::string& d : devices_) {
    auto described = client_.wait_for_device(d, options_.wait, true);
    if (!described) {
      say("no device " + in_quotes(d) + " started within " + wait + " s", true);
      devices_.clear();
      descriptions_.clear();
      return false;
    }
    descriptions_.push_back(std::move(*described));
  }
  connected_ = true;
  return true;
}

void Engine::hook() {
  if (options_.group.empty()) {
    client_.on_state([this](const DeviceState& s) {
      if (s.device != devices_.front()) return;
      const DeviceState* one[] = {&s};
      answer(one, s.serial);
    });
  } else {
    client_.on_group_state([this](const GroupState& g) {
      const auto n = static_cast<std::size_t>(g.device_count);
      if (g.group != options_.group || n != devices_.size() || n > g.states.size()) return;
      std::array<const DeviceState*, kMaxGroupDevices> states{};
      for (std::size_t i = 0; i < n; ++i) states[i] = &g.states[i];
      answer(std::span(states.data(), n), g.serial);
    });
  }
  client_.on_event([this](const Event& e) {
    if (e.kind != EventKind::parameter || std::find(devices_.begin(), devices_.end(), e.device) == devices_.end())
      return;
    {
      std::lock_guard lock(mutex_);
      parameter_events_.emplace_back(e, answered());
    }
    wake_.notify_all();
  });
}

void Engine::unhook() {
  client_.on_state({});
  client_.on_group_state({});
  client_.on_event({});
}

void Engine::answer(std::span<const DeviceState* const> states, std::uint64_t serial) {
  seen_.fetch_add(1, std::memory_order_relaxed);
  for (const DeviceState* s : states)
    if (s->mode == Mode::stopping || s->mode == Mode::off) session_ending_.store(true, std::memory_order_relaxed);
  if (!running_.load(std::memory_order_acquire)) return;
  if (serial <= last_serial_.load(std::memory_order_relaxed)) return;  // a state sent again: answered already
  last_serial_.store(serial, std::memory_order_relaxed);
  std::span<EngineCommand> commands(commands_.data(), states.size());
  std::fill(commands.begin(), commands.end(), EngineCommand{});
  bool send = false;
  try {
    send = answer_(states, commands);
  } catch (const std::exception& e) {
    running_.store(false, std::memory_order_release);
    {
      std::lock_guard lock(mutex_);
      answer_error_ = std::string("answering a state failed: ") + e.what();
    }
    wake_.notify_all();
    return;
  }
  if (!send) return;
  for (std::size_t i = 0; i < states.size(); ++i) {
    commands[i].state_serial = states[i]->serial;
    group_commands_[i].command = commands[i];
  }
  const bool group = !options_.group.empty();
  const std::span<const DeviceCommand> out(group_commands_.data(), states.size());
  bool sent = false;
  if (send_)
    sent = send_(group ? std::string_view(options_.group) : std::string_view(devices_.front()), group, out);
  else
    sent = group ? client_.send_group(options_.group, out) : client_.send(devices_.front(), commands.front());
  if (sent) answered_.fetch_add(1, std::memory_order_relaxed);
}

bool Engine::claim(bool again) {
  running_.store(false, std::memory_order_release);
  const Reply reply = options_.group.empty() ? client_.claim(target_) : client_.claim_group(target_);
  if (!reply.accepted) {
    say("cannot claim " + in_quotes(target_) + (again ? " again: " : ": ") +
            (reply.answered ? reply.message : std::string("no reply")),
        true);
    return false;
  }
  if (on_claim_ && !on_claim_(again)) {
    (void)(options_.group.empty() ? client_.release(target_, std::chrono::milliseconds(500))
                                  : client_.release_group(target_, std::chrono::milliseconds(500)));
    return false;
  }
  // A restarted server counts its states from 1 again; the receive thread sees this before the next answer.
  last_serial_.store(0, std::memory_order_relaxed);
  running_.store(true, std::memory_order_release);
  return true;
}

EngineEnd Engine::run(Answer answer) {
  if (!connect()) return {EngineEndReason::no_device, "no device"};
  answer_ = std::move(answer);
  commands_.assign(devices_.size(), EngineCommand{});
  group_commands_.assign(devices_.size(), DeviceCommand{});
  for (std::size_t i = 0; i < devices_.size(); ++i) group_commands_[i].device.assign(devices_[i]);
  hook();
  struct Unhook {
    Engine& e;
    ~Unhook() {
      e.running_.store(false, std::memory_order_release);
      e.unhook();
    }
  } unhook_at_end{*this};
  if (!claim(false)) return {EngineEndReason::claim_refused, "the claim was refused"};

  const auto start = Clock::now();
  auto last_pass = start, last_progress = start;
  std::uint64_t last_seen = seen_.load();
  EngineEnd end;
  const auto ends = [&](EngineEndReason reason, std::string message, bool error) {
    say(message, error);
    end = {reason, std::move(message)};
  };
  for (;;) {
    std::vector<std::pair<Event, std::uint64_t>> events;
    std::string error;
    {
      std::unique_lock lock(mutex_);
      wake_.wait_for(lock, options_.chores_period,
                     [&] { return stop_requested() || !answer_error_.empty() || !parameter_events_.empty(); });
      events.swap(parameter_events_);
      error = answer_error_;
    }
    const auto now = Clock::now();
    if (stop_requested()) {
      end = {EngineEndReason::stopped, "stopped"};
      break;
    }
    if (!error.empty()) {
      ends(EngineEndReason::failed, error, true);
      break;
    }
    if (now - last_pass > kOwnStall) last_progress = now;  // this process stood still, not the server
    last_pass = now;
    for (const auto& [event, answered_then] : events)
      if (on_parameter_) on_parameter_(event, answered_then);
    if (options_.duration.count() > 0.0 && now - start >= options_.duration) {
      end = {EngineEndReason::finished, "finished"};
      break;
    }
    if (on_chores_ && !on_chores_()) {
      end = {EngineEndReason::failed, "a chore ended the run"};
      break;
    }
    if (client_.claim_lost(devices_.front())) {
      say("the server ended the claim of " + in_quotes(target_) +
          " (this engine seemed gone longer than its claim hold); claiming it again");
      if (!claim(true)) {
        end = {EngineEndReason::claim_lost, "the claim was lost to another engine"};
        break;
      }
      say("claimed " + in_quotes(target_) + " again");
    }
    if (const std::uint64_t seen = seen_.load(); seen != last_seen) {
      last_seen = seen;
      last_progress = now;
      continue;
    }
    const bool ending = session_ending_.load();
    if (now - last_progress < (ending ? kEndingSilence : options_.server_timeout)) continue;
    // No state for a while: the session ended (its last states were answered) or the server is gone.
    running_.store(false, std::memory_order_release);
    session_ending_.store(false);
    const std::string why =
        ending ? "the session ended" : "no state for " + seconds_text(options_.server_timeout) + " s";
    if (!options_.wait_for_server) {
      ends(EngineEndReason::session_ended, why, false);
      break;
    }
    say(why + "; waiting up to " + seconds_text(options_.wait) + " s for the server to come back");
    const std::uint64_t before = seen_.load();
    const auto until = Clock::now() + options_.wait;
    while (!stop_requested() && seen_.load() == before && Clock::now() < until)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (stop_requested()) continue;
    if (seen_.load() == before) {
      ends(EngineEndReason::session_ended, "no server came back within " + seconds_text(options_.wait) + " s", false);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));  // its loop runs: the start pose is published
    if (!claim(true)) {
      end = {EngineEndReason::claim_refused, "the claim was refused"};
      break;
    }
    say("the server is back; claimed " + in_quotes(target_) + " again");
    last_progress = last_pass = Clock::now();
    last_seen = seen_.load();
  }
  running_.store(false, std::memory_order_release);
  unhook();
  (void)(options_.group.empty() ? client_.release(target_, std::chrono::milliseconds(500))
                                : client_.release_group(target_, std::chrono::milliseconds(500)));
  return end;
}

}  // namespace hapticd::client
