#pragma once
// The Foxglove WebSocket protocol (subprotocol foxglove.websocket.v1) as far as the live view speaks it: the
// server's JSON messages (server info, advertise, status), its binary message data, and the client's requests
// (subscribe, unsubscribe) read from untrusted text. Pure functions: no sockets here (websocket_server does
// those), so each is tested on its own.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace hapticd::server::live_view {

inline constexpr std::string_view kSubprotocol = "foxglove.websocket.v1";

// A channel the server offers: a topic whose messages are JSON text matching `schema` (a JSON Schema), named
// `schema_name` (Foxglove's well-known names, foxglove.FrameTransforms and so on, make its panels show them).
struct Channel {
  std::uint32_t id = 0;
  std::string topic;
  std::string schema_name;
  std::string schema;
};

[[nodiscard]] std::string server_info_message(std::string_view name, std::string_view session_id);
[[nodiscard]] std::string advertise_message(const std::vector<Channel>& channels);
// level 0 info, 1 warning, 2 error.
[[nodiscard]] std::string status_message(int level, std::string_view text);
// Binary message data: opcode 1, the subscription id (u32) and the log time in ns (u64), little-endian, then the
// payload. Replaces `out`'s contents.
void message_data(std::string& out, std::uint32_t subscription, std::uint64_t time_ns, std::string_view payload);

struct Subscription {
  std::uint32_t id = 0;       // the client's
  std::uint32_t channel = 0;  // ours
};

// A client's text message, read. `invalid` names what is wrong; `unsupported` is a well-formed request of an
// operation this server does not offer (parameters, services, client publishing).
struct ClientRequest {
  enum class Kind { subscribe, unsubscribe, unsupported, invalid };
  Kind kind = Kind::invalid;
  std::vector<Subscription> subscriptions;      // subscribe
  std::vector<std::uint32_t> subscription_ids;  // unsubscribe
  std::string op;                               // as sent
  std::string error;                            // invalid: why
};

// Longest client message read (larger ones are refused before parsing), and deepest nesting of arrays and
// objects accepted.
inline constexpr std::size_t kMaxClientMessageBytes = 64 * 1024;
inline constexpr int kMaxClientNesting = 8;

// Never throws; anything malformed is `invalid` with the reason.
[[nodiscard]] ClientRequest parse_client_request(std::string_view text);

}  // namespace hapticd::server::live_view
