// The C API's engine helper (hapticd/client.h, "the engine helper") over hapticd::client::Engine: the states are
// converted into buffers of the handle's own (no allocation per state), the C callback fills C commands, and the
// commands go out through the client's sender thread as hapticd_client_send's do.
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <string>

#include "c_status.hpp"
#include "c_values.hpp"
#include "client_handle.hpp"
#include "hapticd/client/engine.hpp"

namespace client = hapticd::client;
using hapticd::client_c::bad_name;
using hapticd::client_c::copy_text;
using hapticd::client_c::fail;
using hapticd::client_c::from_c;
using hapticd::client_c::guarded;
using hapticd::client_c::name_of;
using hapticd::client_c::to_c;

struct hapticd_engine {
  hapticd_engine(hapticd_client& c, client::EngineOptions options) : owner(c), engine(c.client, std::move(options)) {}
  hapticd_client& owner;
  client::Engine engine;
  std::atomic<bool> ran{false};
  // The receive thread's: the states as C structs, the commands the callback fills.
  std::array<hapticd_device_state, HAPTICD_MAX_GROUP_DEVICES> states{};
  std::array<hapticd_command, HAPTICD_MAX_GROUP_DEVICES> commands{};
};

static_assert(HAPTICD_ENGINE_FINISHED == static_cast<int>(client::EngineEndReason::finished) &&
              HAPTICD_ENGINE_STOPPED == static_cast<int>(client::EngineEndReason::stopped) &&
              HAPTICD_ENGINE_SESSION_ENDED == static_cast<int>(client::EngineEndReason::session_ended) &&
              HAPTICD_ENGINE_NO_DEVICE == static_cast<int>(client::EngineEndReason::no_device) &&
              HAPTICD_ENGINE_CLAIM_REFUSED == static_cast<int>(client::EngineEndReason::claim_refused) &&
              HAPTICD_ENGINE_CLAIM_LOST == static_cast<int>(client::EngineEndReason::claim_lost) &&
              HAPTICD_ENGINE_FAILED == static_cast<int>(client::EngineEndReason::failed));

namespace {

hapticd_status no_engine() noexcept { return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the engine is NULL"); }

// An optional name argument: NULL or "" is none; else 1..31 characters.
bool optional_name(const char* text, std::string& out) {
  if (text == nullptr || text[0] == '\0') return true;
  const std::string_view name = name_of(text);
  out.assign(name);
  return !name.empty();
}

bool valid_seconds(double s) noexcept { return std::isfinite(s) && s >= 0.0; }

// The C options into the helper's; an error message when one is bad.
std::string options_of(const hapticd_engine_options& in, client::EngineOptions& out) {
  if (in.size < sizeof(hapticd_engine_options)) return "options->size is less than sizeof(hapticd_engine_options)";
  if (in.name != nullptr) out.name = in.name;
  if (!optional_name(in.device, out.device)) return "the device must have 1 to 31 characters";
  if (!optional_name(in.group, out.group)) return "the group must have 1 to 31 characters";
  if (!out.device.empty() && !out.group.empty()) return "a device or a group, not both";
  for (double s : {in.wait_s, in.server_timeout_s, in.duration_s})
    if (!valid_seconds(s)) return "times must be finite and >= 0";
  if (in.wait_s > 0.0) out.wait = client::Timeout(in.wait_s);
  if (in.server_timeout_s > 0.0) out.server_timeout = client::Timeout(in.server_timeout_s);
  out.duration = client::Timeout(in.duration_s);
  out.wait_for_server = in.wait_for_server != 0;
  return {};
}

// The receive thread's answer: C states in, C commands out, converted back for the helper to send.
bool answer_in_c(hapticd_engine& e, hapticd_engine_answer answer, void* user,
                 std::span<const client::DeviceState* const> states, std::span<client::EngineCommand> commands) {
  const std::size_t n = std::min(states.size(), e.states.size());
  for (std::size_t i = 0; i < n; ++i) {
    to_c(*states[i], e.states[i]);
    e.commands[i] = hapticd_command{};
  }
  if (answer(e.states.data(), static_cast<std::int32_t>(n), e.commands.data(), user) == 0) return false;
  for (std::size_t i = 0; i < n; ++i)
    if (!from_c(e.commands[i], commands[i])) return false;  // an unknown kind: nothing sent for these states
  return true;
}

}  // namespace

extern "C" {

hapticd_status hapticd_engine_create(hapticd_client* c, const hapticd_engine_options* options, hapticd_engine** out) {
  if (out == nullptr) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "out is NULL");
  *out = nullptr;
  if (c == nullptr || options == nullptr) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the client or options is NULL");
  return guarded([&] {
    client::EngineOptions o;
    if (const std::string e = options_of(*options, o); !e.empty()) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, e);
    auto* engine = new hapticd_engine(*c, std::move(o));
    engine->engine.send_through([engine](std::string_view target, bool group,
                                         std::span<const client::DeviceCommand> commands) {
      using Result = hapticd::client_c::CommandSender::Result;
      if (!group) return engine->owner.sender.send(target, commands.front().command) == Result::handed_over;
      std::array<client::DeviceCommand, client::kMaxGroupDevices> list{};
      std::copy(commands.begin(), commands.end(), list.begin());
      return engine->owner.sender.send_group(target, list, static_cast<int>(commands.size())) == Result::handed_over;
    });
    *out = engine;
    return HAPTICD_OK;
  });
}

void hapticd_engine_destroy(hapticd_engine* engine) {
  try {
    delete engine;
  } catch (...) {  // never across C
  }
}

hapticd_status hapticd_engine_connect(hapticd_engine* e) {
  if (e == nullptr) return no_engine();
  return guarded([&] {
    return e->engine.connect() ? HAPTICD_OK : fail(HAPTICD_ERROR_NOT_FOUND, "the device or group did not start");
  });
}

hapticd_status hapticd_engine_device_count(hapticd_engine* e, int32_t* count) {
  if (e == nullptr || count == nullptr) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the engine or count is NULL");
  *count = static_cast<int32_t>(e->engine.devices().size());
  return HAPTICD_OK;
}

hapticd_status hapticd_engine_device(hapticd_engine* e, int32_t index, hapticd_device_info* out) {
  if (e == nullptr || out == nullptr) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the engine or out is NULL");
  if (index < 0 || static_cast<std::size_t>(index) >= e->engine.devices().size())
    return fail(HAPTICD_ERROR_NOT_FOUND, "no such device index (connect first)");
  return guarded([&] {
    to_c(e->engine.description(static_cast<std::size_t>(index)), *out);
    return HAPTICD_OK;
  });
}

hapticd_status hapticd_engine_on_claim(hapticd_engine* e, hapticd_engine_claim_hook hook, void* user) {
  if (e == nullptr) return no_engine();
  return guarded([&] {
    e->engine.on_claim(hook == nullptr ? client::Engine::ClaimHook{}
                                       : [hook, user](bool again) { return hook(again ? 1 : 0, user) != 0; });
    return HAPTICD_OK;
  });
}

hapticd_status hapticd_engine_on_chores(hapticd_engine* e, hapticd_engine_chores_hook hook, void* user) {
  if (e == nullptr) return no_engine();
  return guarded([&] {
    e->engine.on_chores(hook == nullptr ? client::Engine::ChoresHook{} : [hook, user] { return hook(user) != 0; });
    return HAPTICD_OK;
  });
}

hapticd_status hapticd_engine_on_parameter(hapticd_engine* e, hapticd_engine_parameter_hook hook, void* user) {
  if (e == nullptr) return no_engine();
  return guarded([&] {
    e->engine.on_parameter(hook == nullptr ? client::Engine::ParameterHook{}
                                           : [hook, user](const client::Event& event, std::uint64_t then) {
                                               hapticd_event c{};
                                               to_c(event, c);
                                               hook(&c, then, user);
                                             });
    return HAPTICD_OK;
  });
}

hapticd_status hapticd_engine_run(hapticd_engine* e, hapticd_engine_answer answer, void* user,
                                  hapticd_engine_end* end) {
  if (e == nullptr || answer == nullptr) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the engine or answer is NULL");
  if (e->ran.exchange(true)) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "an engine runs once");
  return guarded([&] {
    const client::EngineEnd result = e->engine.run([e, answer, user](std::span<const client::DeviceState* const> states,
                                                                     std::span<client::EngineCommand> commands) {
      return answer_in_c(*e, answer, user, states, commands);
    });
    if (end != nullptr) {
      end->reason = static_cast<int32_t>(result.reason);
      end->exit_code = result.exit_code();
      copy_text(end->message, result.message);
    }
    return HAPTICD_OK;
  });
}

hapticd_status hapticd_engine_stop(hapticd_engine* e) {
  if (e == nullptr) return no_engine();
  e->engine.stop();
  return HAPTICD_OK;
}

hapticd_status hapticd_engine_answered(hapticd_engine* e, uint64_t* answered) {
  if (e == nullptr || answered == nullptr)
    return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the engine or answered is NULL");
  *answered = e->engine.answered();
  return HAPTICD_OK;
}

}  // extern "C"
