// The C API (hapticd/client.h) over the C++ client library: each function checks its arguments, calls the
// library, converts its values, and turns every exception into a status and the thread's message. Nothing of
// C++ leaves this file through the interface.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <deque>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

#include "c_status.hpp"
#include "c_values.hpp"
#include "client_handle.hpp"
#include "hapticd/client.h"
#include "hapticd/client/client.hpp"

namespace {

using hapticd::client_c::bad_name;
using hapticd::client_c::copy_text;
using hapticd::client_c::fail;
using hapticd::client_c::from_c;
using hapticd::client_c::guarded;
using hapticd::client_c::name_of;
using hapticd::client_c::to_c;
using hapticd::client_c::valid_timeout;
namespace client = hapticd::client;

client::Timeout timeout_of(double seconds) noexcept { return client::Timeout(seconds); }

hapticd_status reply_status(const client::Reply& r, hapticd_reply* out) noexcept {
  if (out != nullptr) to_c(r, *out);
  if (!r.answered) return fail(HAPTICD_ERROR_TIMEOUT, "no reply within the timeout");
  if (!r.accepted) return fail(HAPTICD_ERROR_REFUSED, r.message);
  return HAPTICD_OK;
}

// The common checks of a request on a named device or group, then the request.
template <class F>
hapticd_status request(hapticd_client* c, const char* target, const char* what, double timeout_s, hapticd_reply* reply,
                       F&& f) noexcept {
  if (c == nullptr) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the client is NULL");
  const std::string_view name = name_of(target);
  if (name.empty()) return bad_name(what, target);
  if (!valid_timeout(timeout_s)) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the timeout must be finite and >= 0");
  return guarded([&] { return reply_status(f(name, timeout_of(timeout_s)), reply); });
}

bool heard_of_group(hapticd_client* c, std::string_view name) {
  for (const auto& g : c->client.groups())
    if (g.group == name) return true;
  return false;
}
bool heard_of_device(hapticd_client* c, std::string_view name) {
  for (const auto& d : c->client.devices())
    if (d.device == name) return true;
  return false;
}

// Whether `target` names a group: "*" (every device of the server), a group this client has heard of, or - neither
// heard of yet - a group heard of first within the timeout. Returns the time left of the timeout in `left`.
bool names_group(hapticd_client* c, std::string_view target, double timeout_s, client::Timeout& left) {
  using Clock = std::chrono::steady_clock;
  const auto deadline =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeout_s));
  const auto remaining = [&] {
    return client::Timeout(std::max(0.0, std::chrono::duration<double>(deadline - Clock::now()).count()));
  };
  if (target == "*") {
    left = remaining();
    return true;
  }
  for (;;) {
    if (heard_of_group(c, target)) {
      left = remaining();
      return true;
    }
    if (heard_of_device(c, target)) {
      left = remaining();
      return false;
    }
    if (Clock::now() >= deadline) {
      left = client::Timeout(0.0);
      return false;  // the server says it has no such device
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

std::vector<double> values_of(const double* values, std::int32_t count) {
  return count > 0 ? std::vector<double>(values, values + count) : std::vector<double>{};
}

bool valid_values(const double* values, std::int32_t count) noexcept {
  return count >= 0 && count <= HAPTICD_MAX_VALUES && (count == 0 || values != nullptr);
}

// One thing of a named device or group into `out`: the arguments checked (the timeout when `timed`), then
// `get(name)`, an optional; nothing is `missing` (HAPTICD_ERROR_TIMEOUT or HAPTICD_ERROR_NOT_FOUND), said with
// `thing`. The success path allocates nothing (hapticd_client_latest_state relies on it).
template <class Out, class Get>
hapticd_status fetch(hapticd_client* c, const char* target, const char* what, bool timed, double timeout_s, Out* out,
                     const char* thing, hapticd_status missing, Get&& get) noexcept {
  if (c == nullptr || out == nullptr) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the client or out is NULL");
  const std::string_view name = name_of(target);
  if (name.empty()) return bad_name(what, target);
  if (timed && !valid_timeout(timeout_s))
    return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the timeout must be finite and >= 0");
  return guarded([&] {
    const auto value = get(name);
    if (!value)
      return fail(missing, std::string("no ") + thing + " of '" + std::string(name) + "'" +
                               (missing == HAPTICD_ERROR_TIMEOUT ? " within the timeout" : " yet"));
    to_c(*value, *out);
    return HAPTICD_OK;
  });
}

hapticd_status handed_over(hapticd::client_c::CommandSender::Result r) noexcept {
  using Result = hapticd::client_c::CommandSender::Result;
  switch (r) {
    case Result::handed_over:
      return HAPTICD_OK;
    case Result::no_slot:
      return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "a client commands at most 16 devices and groups");
    case Result::previous_write_failed:
      return fail(HAPTICD_ERROR_DDS, "the previous command to this target could not be written (not permitted?)");
  }
  return HAPTICD_ERROR_INTERNAL;
}

}  // namespace

extern "C" {

int hapticd_api_version(void) { return HAPTICD_C_API_VERSION; }

const char* hapticd_last_error(void) { return hapticd::client_c::last_error_text(); }

const char* hapticd_status_name(hapticd_status status) {
  switch (status) {
    case HAPTICD_OK:
      return "HAPTICD_OK";
    case HAPTICD_ERROR_INVALID_ARGUMENT:
      return "HAPTICD_ERROR_INVALID_ARGUMENT";
    case HAPTICD_ERROR_NOT_FOUND:
      return "HAPTICD_ERROR_NOT_FOUND";
    case HAPTICD_ERROR_TIMEOUT:
      return "HAPTICD_ERROR_TIMEOUT";
    case HAPTICD_ERROR_REFUSED:
      return "HAPTICD_ERROR_REFUSED";
    case HAPTICD_ERROR_DDS:
      return "HAPTICD_ERROR_DDS";
    case HAPTICD_ERROR_INTERNAL:
      return "HAPTICD_ERROR_INTERNAL";
  }
  return "an unknown status";
}

hapticd_status hapticd_client_create(const hapticd_client_options* options, hapticd_client** out) {
  if (out == nullptr) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "out is NULL");
  *out = nullptr;
  if (options == nullptr) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the options are NULL");
  if (options->size < sizeof(hapticd_client_options))
    return fail(HAPTICD_ERROR_INVALID_ARGUMENT,
                "options->size is less than sizeof(hapticd_client_options) (set .size = sizeof options)");
  const std::string_view id = name_of(options->client_id);
  if (id.empty()) return bad_name("the client id", options->client_id);
  if (options->domain_id < 0 || options->domain_id > 230)
    return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the DDS domain must be 0 to 230");
  if (!(options->command_deadline_s >= 0.0) || !std::isfinite(options->command_deadline_s))
    return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the command deadline must be finite and >= 0");
  return guarded([&] {
    client::ClientOptions o{std::string(id), options->domain_id};
    if (options->cyclone_config != nullptr) o.cyclone_config = options->cyclone_config;
    if (options->network != nullptr) o.network = options->network;
    if (options->command_deadline_s > 0.0) o.command_deadline_s = options->command_deadline_s;
    try {
      *out = new hapticd_client(std::move(o));
    } catch (const std::invalid_argument& e) {  // the network or configuration text
      return fail(HAPTICD_ERROR_INVALID_ARGUMENT, e.what());
    } catch (const std::runtime_error& e) {  // the participant could not be made
      return fail(HAPTICD_ERROR_DDS, e.what());
    }
    return HAPTICD_OK;
  });
}

void hapticd_client_destroy(hapticd_client* client) {
  try {
    delete client;
  } catch (...) {  // a destructor that throws is the library's bug; never across C
  }
}

// ---- devices ----

hapticd_status hapticd_client_list_devices(hapticd_client* c, hapticd_device_info* out, int32_t capacity,
                                           int32_t* count) {
  if (c == nullptr || count == nullptr || capacity < 0 || (capacity > 0 && out == nullptr))
    return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the client, count or out is NULL (or capacity < 0)");
  return guarded([&] {
    const auto devices = c->client.devices();
    *count = static_cast<int32_t>(devices.size());
    for (std::size_t i = 0; i < devices.size() && i < static_cast<std::size_t>(capacity); ++i) to_c(devices[i], out[i]);
    return HAPTICD_OK;
  });
}

hapticd_status hapticd_client_wait_for_device(hapticd_client* c, const char* device, double timeout_s, int32_t started,
                                              hapticd_device_info* out) {
  return fetch(c, device, "the device", true, timeout_s, out, "description", HAPTICD_ERROR_TIMEOUT,
               [&](std::string_view d) { return c->client.wait_for_device(d, timeout_of(timeout_s), started != 0); });
}

hapticd_status hapticd_client_latest_state(hapticd_client* c, const char* device, hapticd_device_state* out) {
  return fetch(c, device, "the device", false, 0.0, out, "state", HAPTICD_ERROR_NOT_FOUND,
               [&](std::string_view d) { return c->client.latest_state(d); });
}

hapticd_status hapticd_client_wait_for_state(hapticd_client* c, const char* device, double timeout_s, uint64_t after,
                                             hapticd_device_state* out) {
  return fetch(c, device, "the device", true, timeout_s, out, "state", HAPTICD_ERROR_TIMEOUT,
               [&](std::string_view d) { return c->client.wait_for_state(d, timeout_of(timeout_s), after); });
}

// ---- groups ----

hapticd_status hapticd_client_list_groups(hapticd_client* c, hapticd_group_info* out, int32_t capacity,
                                          int32_t* count) {
  if (c == nullptr || count == nullptr || capacity < 0 || (capacity > 0 && out == nullptr))
    return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the client, count or out is NULL (or capacity < 0)");
  return guarded([&] {
    const auto groups = c->client.groups();
    *count = static_cast<int32_t>(groups.size());
    for (std::size_t i = 0; i < groups.size() && i < static_cast<std::size_t>(capacity); ++i) to_c(groups[i], out[i]);
    return HAPTICD_OK;
  });
}

hapticd_status hapticd_client_wait_for_group(hapticd_client* c, const char* group, double timeout_s,
                                             hapticd_group_info* out) {
  return fetch(c, group, "the group", true, timeout_s, out, "group description", HAPTICD_ERROR_TIMEOUT,
               [&](std::string_view g) { return c->client.wait_for_group(g, timeout_of(timeout_s)); });
}

hapticd_status hapticd_client_latest_group_state(hapticd_client* c, const char* group, hapticd_group_state* out) {
  return fetch(c, group, "the group", false, 0.0, out, "group state", HAPTICD_ERROR_NOT_FOUND,
               [&](std::string_view g) { return c->client.latest_group_state(g); });
}

hapticd_status hapticd_client_wait_for_group_state(hapticd_client* c, const char* group, double timeout_s,
                                                   uint64_t after, hapticd_group_state* out) {
  return fetch(c, group, "the group", true, timeout_s, out, "group state", HAPTICD_ERROR_TIMEOUT,
               [&](std::string_view g) { return c->client.wait_for_group_state(g, timeout_of(timeout_s), after); });
}

// ---- events, telemetry, fault reports ----

hapticd_status hapticd_client_take_events(hapticd_client* c, hapticd_event* out, int32_t capacity, int32_t* count) {
  if (c == nullptr || count == nullptr || capacity < 0 || (capacity > 0 && out == nullptr))
    return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the client, count or out is NULL (or capacity < 0)");
  return guarded([&] {
    std::lock_guard lock(c->events_mutex);
    for (auto& e : c->client.take_events()) c->pending_events.push_back(std::move(e));
    while (c->pending_events.size() > 1024) c->pending_events.pop_front();  // the library's bound
    int32_t n = 0;
    while (n < capacity && !c->pending_events.empty()) {
      to_c(c->pending_events.front(), out[n++]);
      c->pending_events.pop_front();
    }
    *count = n;
    return HAPTICD_OK;
  });
}

hapticd_status hapticd_client_latest_telemetry(hapticd_client* c, const char* device, hapticd_telemetry* out) {
  return fetch(c, device, "the device", false, 0.0, out, "telemetry", HAPTICD_ERROR_NOT_FOUND,
               [&](std::string_view d) { return c->client.latest_telemetry(d); });
}

hapticd_status hapticd_client_latest_fault_report(hapticd_client* c, const char* device, hapticd_fault_report* out) {
  return fetch(c, device, "the device", false, 0.0, out, "fault report", HAPTICD_ERROR_NOT_FOUND,
               [&](std::string_view d) { return c->client.latest_fault_report(d); });
}

// ---- callbacks ----

hapticd_status hapticd_client_on_state(hapticd_client* c, const char* device, hapticd_state_callback callback,
                                       void* user) {
  if (c == nullptr) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the client is NULL");
  client::Name only;  // "": every device
  if (device != nullptr && *device != '\0') {
    const std::string_view name = name_of(device);
    if (name.empty()) return bad_name("the device", device);
    only.assign(name);
  }
  return guarded([&] {
    if (callback == nullptr) {
      c->client.on_state({});
    } else {
      c->client.on_state([callback, user, only](const client::DeviceState& s) {
        if (!only.empty() && s.device.view() != only.view()) return;
        hapticd_device_state state;  // on the receive thread's stack: no allocation per state
        to_c(s, state);
        callback(&state, user);
      });
    }
    return HAPTICD_OK;
  });
}

hapticd_status hapticd_client_on_event(hapticd_client* c, hapticd_event_callback callback, void* user) {
  if (c == nullptr) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the client is NULL");
  return guarded([&] {
    if (callback == nullptr) {
      c->client.on_event({});
    } else {
      c->client.on_event([callback, user](const client::Event& e) {
        hapticd_event event;
        to_c(e, event);
        callback(&event, user);
      });
    }
    return HAPTICD_OK;
  });
}

hapticd_status hapticd_client_on_claim_lost(hapticd_client* c, hapticd_claim_lost_callback callback, void* user) {
  if (c == nullptr) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the client is NULL");
  return guarded([&] {
    if (callback == nullptr) {
      c->client.on_claim_lost({});
    } else {
      c->client.on_claim_lost([callback, user](std::string_view device, std::string_view reason) {
        char d[HAPTICD_NAME_SIZE];
        char r[HAPTICD_MESSAGE_SIZE];
        copy_text(d, device);
        copy_text(r, reason);
        callback(d, r, user);
      });
    }
    return HAPTICD_OK;
  });
}

hapticd_status hapticd_client_claim_lost(hapticd_client* c, const char* device, int32_t* lost) {
  if (c == nullptr || lost == nullptr) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the client or lost is NULL");
  const std::string_view name = name_of(device);
  if (name.empty()) return bad_name("the device", device);
  return guarded([&] {
    *lost = c->client.claim_lost(name) ? 1 : 0;
    return HAPTICD_OK;
  });
}

// ---- requests ----

// A request on a device or a group: the group's form when `target` names a group (names_group), else the device's.
using TargetRequest = client::Reply (client::Client::*)(std::string_view, client::Timeout);
hapticd_status device_or_group(hapticd_client* c, const char* target, double timeout_s, hapticd_reply* reply,
                               TargetRequest on_device, TargetRequest on_group) noexcept {
  return request(c, target, "the device or group", timeout_s, reply, [&](std::string_view t, client::Timeout) {
    client::Timeout left(0.0);
    return (c->client.*(names_group(c, t, timeout_s, left) ? on_group : on_device))(t, left);
  });
}

hapticd_status hapticd_client_claim(hapticd_client* c, const char* target, double timeout_s, hapticd_reply* reply) {
  return device_or_group(c, target, timeout_s, reply, &client::Client::claim, &client::Client::claim_group);
}

hapticd_status hapticd_client_release(hapticd_client* c, const char* target, double timeout_s, hapticd_reply* reply) {
  return device_or_group(c, target, timeout_s, reply, &client::Client::release, &client::Client::release_group);
}

hapticd_status hapticd_client_switch_scheme(hapticd_client* c, const char* device, const char* scheme, double timeout_s,
                                            hapticd_reply* reply) {
  const std::string_view s = name_of(scheme);
  if (s.empty()) return bad_name("the scheme", scheme);
  return request(c, device, "the device", timeout_s, reply,
                 [&](std::string_view d, client::Timeout t) { return c->client.switch_scheme(d, s, t); });
}

hapticd_status hapticd_client_set_parameter(hapticd_client* c, const char* device, const char* parameter,
                                            const double* values, int32_t value_count, double timeout_s,
                                            hapticd_reply* reply) {
  if (parameter == nullptr || *parameter == '\0')
    return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the parameter is NULL or empty");
  if (!valid_values(values, value_count))
    return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "values: 0 to 16, and not NULL when there are some");
  return request(c, device, "the device", timeout_s, reply, [&](std::string_view d, client::Timeout t) {
    return c->client.set_parameter(d, parameter, values_of(values, value_count), t);
  });
}

hapticd_status hapticd_client_get_parameter(hapticd_client* c, const char* device, const char* parameter,
                                            double timeout_s, hapticd_reply* reply) {
  if (parameter == nullptr || *parameter == '\0')
    return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the parameter is NULL or empty");
  return request(c, device, "the device", timeout_s, reply,
                 [&](std::string_view d, client::Timeout t) { return c->client.get_parameter(d, parameter, t); });
}

hapticd_status hapticd_client_describe_parameter(hapticd_client* c, const char* device, const char* parameter,
                                                 double timeout_s, hapticd_parameter_info* out, hapticd_reply* reply) {
  if (parameter == nullptr || *parameter == '\0' || out == nullptr)
    return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the parameter or out is NULL (or the parameter empty)");
  return request(c, device, "the device", timeout_s, reply, [&](std::string_view d, client::Timeout t) {
    auto answer = c->client.describe_parameter(d, parameter, t);
    if (answer.info) to_c(*answer.info, *out);
    return answer.reply;
  });
}

// A stop is sent at once, never after a wait for a description: a name heard of as a group (or "*") stops the group;
// any other is stopped as a device and, if the server has no such device, as a group.
hapticd_status hapticd_client_emergency_stop(hapticd_client* c, const char* target, double timeout_s,
                                             hapticd_reply* reply) {
  return request(c, target, "the device or group", timeout_s, reply, [&](std::string_view t, client::Timeout left) {
    if (t == "*" || heard_of_group(c, t)) return c->client.emergency_stop_group(t, left);
    client::Reply r = c->client.emergency_stop(t, left);
    if (r.answered && !r.accepted && !heard_of_device(c, t)) {
      client::Reply g = c->client.emergency_stop_group(t, left);
      if (g.answered && g.accepted) return g;
    }
    return r;
  });
}

hapticd_status hapticd_client_recover(hapticd_client* c, const char* target, double timeout_s, hapticd_reply* reply) {
  return device_or_group(c, target, timeout_s, reply, &client::Client::recover, &client::Client::recover_group);
}

hapticd_status hapticd_client_operator_command(hapticd_client* c, const char* device, const char* command,
                                               const double* values, int32_t value_count, double timeout_s,
                                               hapticd_reply* reply) {
  const std::string_view name = name_of(command);
  if (name.empty()) return bad_name("the operator command", command);
  if (!valid_values(values, value_count))
    return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "values: 0 to 16, and not NULL when there are some");
  return request(c, device, "the device", timeout_s, reply, [&](std::string_view d, client::Timeout t) {
    return c->client.operator_command(d, name, values_of(values, value_count), t);
  });
}

// ---- engine commands (no allocation: fixed-size values, handed to the sender thread) ----

hapticd_status hapticd_client_send(hapticd_client* c, const char* device, const hapticd_command* command) {
  if (c == nullptr || command == nullptr) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the client or command is NULL");
  const std::string_view name = name_of(device);
  if (name.empty()) return bad_name("the device", device);
  client::EngineCommand cmd;
  if (!from_c(*command, cmd)) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "an unknown command kind");
  return handed_over(c->sender.send(name, cmd));
}

hapticd_status hapticd_client_send_coupling(hapticd_client* c, const char* device, const hapticd_pose* proxy,
                                            const hapticd_twist* proxy_twist, uint64_t state_serial) {
  if (c == nullptr || proxy == nullptr) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the client or proxy is NULL");
  const std::string_view name = name_of(device);
  if (name.empty()) return bad_name("the device", device);
  const hapticd::Twist twist = proxy_twist != nullptr ? from_c(*proxy_twist) : hapticd::Twist{};
  return handed_over(c->sender.send(name, client::EngineCommand::coupling(from_c(*proxy), twist, state_serial)));
}

hapticd_status hapticd_client_send_wrench(hapticd_client* c, const char* device, const hapticd_wrench* wrench,
                                          const hapticd_local_model* local_model, uint64_t state_serial) {
  if (c == nullptr || wrench == nullptr) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the client or wrench is NULL");
  const std::string_view name = name_of(device);
  if (name.empty()) return bad_name("the device", device);
  hapticd_command command{};
  command.kind = HAPTICD_COMMAND_WRENCH;
  command.state_serial = state_serial;
  command.wrench = *wrench;
  command.pose.orientation.w = 1.0;
  if (local_model != nullptr) {
    command.has_local_model = 1;
    command.local_model = *local_model;
  }
  client::EngineCommand cmd;
  (void)from_c(command, cmd);
  return handed_over(c->sender.send(name, cmd));
}

hapticd_status hapticd_client_send_motion(hapticd_client* c, const char* device, const hapticd_pose* pose,
                                          const hapticd_twist* twist, uint64_t state_serial) {
  if (c == nullptr || pose == nullptr) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the client or pose is NULL");
  const std::string_view name = name_of(device);
  if (name.empty()) return bad_name("the device", device);
  const hapticd::Twist t = twist != nullptr ? from_c(*twist) : hapticd::Twist{};
  return handed_over(c->sender.send(name, client::EngineCommand::motion(from_c(*pose), t, state_serial)));
}

hapticd_status hapticd_client_send_group(hapticd_client* c, const char* group, const hapticd_command* commands,
                                         int32_t count) {
  if (c == nullptr || commands == nullptr)
    return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the client or commands is NULL");
  const std::string_view name = name_of(group);
  if (name.empty()) return bad_name("the group", group);
  if (count < 1 || count > HAPTICD_MAX_GROUP_DEVICES)
    return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "a group command has 1 to 8 device commands");
  std::array<client::DeviceCommand, HAPTICD_MAX_GROUP_DEVICES> list{};
  for (int32_t i = 0; i < count; ++i) {
    const hapticd_command& in = commands[i];
    const std::string_view device = name_of(in.device);
    if (device.empty()) return bad_name("a command's device", in.device);
    list[static_cast<std::size_t>(i)].device = device;
    if (!from_c(in, list[static_cast<std::size_t>(i)].command))
      return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "an unknown command kind");
  }
  return handed_over(c->sender.send_group(name, list, count));
}

}  // extern "C"
