#pragma once
// The engine socket's JSON messages (docs/engine-socket.md), shaped after Haply's Inverse Service where they fit:
// an inventory on connecting, one state per message, `set_cursor_force` under a device's "commands". Parsing
// turns a client's message into the DDS interface's own messages (EngineCommand, ControlRequest), so that the
// gate checks them exactly as it checks a DDS client's; writing turns the published DeviceState into JSON.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gate/scene_gate.hpp"
#include "hapticd/json_reader.hpp"
#include "hapticd_msg.h"

namespace hapticd::server::socket_messages {

// An edit of the session's haptic scene ({"scene": {"id": 1, "op": "add", "object": {...}}}); its name and text
// point into the parsed message.
struct SceneMessage {
  std::int64_t id = 0;
  SceneGate::Edit edit;
};

// What one client message asks for. A message may carry commands (for one or more devices), one request, one
// scene edit, a subscription and a session profile at once.
struct ClientMessage {
  std::vector<hapticd_msg_EngineCommand> commands;  // at most kMaxCommands
  std::optional<hapticd_msg_ControlRequest> request;
  std::optional<SceneMessage> scene;
  std::string scene_text;                      // the scene edit's text, when made here (a material's name, quoted)
  std::vector<double> scene_vertices;          // an upload's part: its vertices and triangles (the edit's spans
  std::vector<std::uint32_t> scene_triangles;  // point here)
  std::optional<std::vector<std::string>> subscribe;  // the devices whose states it wants ([]: none)
  std::optional<std::string> profile;                 // session.configure.profile.name: its client id
  std::string error;                                  // "": well-formed; else why not (nothing of it applies)
};
inline constexpr std::size_t kMaxCommands = 8;

// A parser that keeps its storage: a command message a thousand times a second reuses it.
class Parser {
 public:
  Parser() : json_(2048) {}
  // Parses `text` into `out` (cleared first). engine: the connection's client id (each command's `engine`);
  // serial: the connection's command counter (each command takes the next). False with out.error set when the
  // message is malformed; nothing of it is then to be applied.
  bool parse(std::string_view text, std::string_view engine, std::uint64_t& serial, ClientMessage& out);

 private:
  bool command(const JsonReader::Value& entry, std::string_view engine, std::uint64_t& serial,
               std::uint64_t state_serial, ClientMessage& out);
  bool request(const JsonReader::Value& r, std::string_view client, ClientMessage& out);
  bool scene(const JsonReader::Value& s, ClientMessage& out);
  JsonReader json_;
};

// A device's inventory entry as the server knows it.
struct InventoryDevice {
  std::string name, model, interface, scheme;
  int dof = 0;
  bool simulated = false;
  std::vector<std::string> schemes;
  double command_deadline_s = 0.0;
  std::array<double, 3> base_position{};
  std::array<double, 4> base_orientation{1, 0, 0, 0};
};
struct InventoryGroup {
  std::string name;
  std::vector<std::string> devices;
};

// The first message: the session, the client id the connection has, every device and group.
[[nodiscard]] std::string inventory(std::uint64_t session_id, std::string_view client,
                                    const std::vector<InventoryDevice>& devices,
                                    const std::vector<InventoryGroup>& groups);
// One device's state (written into `out`, its storage reused).
void state(const hapticd_msg_DeviceState& s, std::string& out);
// The answer to a scene edit ({"scene_reply": {"id", "accepted", "message"[, "objects"]}}).
[[nodiscard]] std::string scene_reply(std::int64_t id, const SceneGate::Reply& r);
// The answer to a request.
[[nodiscard]] std::string reply(std::int64_t id, const hapticd_msg_ControlReply& r);
// A device's event (what the DDS interface's Event says): kind as a name ("parameter", "owner", ...).
[[nodiscard]] std::string event(const hapticd_msg_Event& e);
[[nodiscard]] std::string_view event_kind_name(std::int32_t kind);
// A message that was not applied (malformed, refused by the gate, dropped by the rate limit); count: how many of
// its kind so far.
[[nodiscard]] std::string error(std::string_view code, std::string_view message, std::uint64_t count);

}  // namespace hapticd::server::socket_messages
