#include "live_view/foxglove_protocol.hpp"

#include <boost/property_tree/json_parser.hpp>
#include <boost/property_tree/ptree.hpp>
#include <charconv>
#include <sstream>

#include "hapticd/json_text.hpp"

namespace hapticd::server::live_view {

using namespace json_text;

std::string server_info_message(std::string_view name, std::string_view session_id) {
  std::string out = "{\"op\":\"serverInfo\",\"name\":";
  append_string(out, name);
  out += ",\"capabilities\":[],\"sessionId\":";
  append_string(out, session_id);
  out += '}';
  return out;
}

std::string advertise_message(const std::vector<Channel>& channels) {
  std::string out = "{\"op\":\"advertise\",\"channels\":[";
  bool first = true;
  for (const Channel& c : channels) {
    if (!first) out += ',';
    first = false;
    out += "{\"id\":";
    append_integer(out, c.id);
    append_key(out, "topic");
    append_string(out, c.topic);
    out += ",\"encoding\":\"json\",\"schemaName\":";
    append_string(out, c.schema_name);
    out += ",\"schemaEncoding\":\"jsonschema\",\"schema\":";
    append_string(out, c.schema);
    out += '}';
  }
  out += "]}";
  return out;
}

std::string status_message(int level, std::string_view text) {
  std::string out = "{\"op\":\"status\",\"level\":";
  append_integer(out, level);
  out += ",\"message\":";
  append_string(out, text);
  out += '}';
  return out;
}

void message_data(std::string& out, std::uint32_t subscription, std::uint64_t time_ns, std::string_view payload) {
  out.clear();
  out.reserve(13 + payload.size());
  out += static_cast<char>(0x01);
  for (int b = 0; b < 4; ++b) out += static_cast<char>((subscription >> (8 * b)) & 0xffu);
  for (int b = 0; b < 8; ++b) out += static_cast<char>((time_ns >> (8 * b)) & 0xffu);
  out.append(payload);
}

namespace {

using boost::property_tree::ptree;

// Deepest nesting of arrays and objects outside strings (the parser recurses: a deeply nested message must not
// reach it).
int nesting(std::string_view text) {
  int depth = 0, deepest = 0;
  bool in_string = false, escaped = false;
  for (const char c : text) {
    if (in_string) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == '"')
        in_string = false;
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return deepest;
}

// A non-negative integer that fits 32 bits (the ids of the protocol), or false.
bool read_id(const ptree& node, std::uint32_t& out) {
  if (!node.empty()) return false;  // an object or array
  const std::string& text = node.data();
  const auto result = std::from_chars(text.data(), text.data() + text.size(), out);
  return result.ec == std::errc() && result.ptr == text.data() + text.size() && !text.empty();
}

ClientRequest invalid(std::string why, std::string op = {}) {
  ClientRequest r;
  r.kind = ClientRequest::Kind::invalid;
  r.error = std::move(why);
  r.op = std::move(op);
  return r;
}

}  // namespace

ClientRequest parse_client_request(std::string_view text) {
  if (text.size() > kMaxClientMessageBytes)
    return invalid("message of " + std::to_string(text.size()) + " bytes (at most " +
                   std::to_string(kMaxClientMessageBytes) + ")");
  if (nesting(text) > kMaxClientNesting) return invalid("nested deeper than " + std::to_string(kMaxClientNesting));
  ptree root;
  try {
    std::istringstream in{std::string(text)};
    boost::property_tree::read_json(in, root);
  } catch (const std::exception&) {
    return invalid("not a JSON object");
  }
  const auto op_node = root.get_child_optional("op");
  if (!op_node || !op_node->empty()) return invalid("no \"op\"");
  ClientRequest r;
  r.op = op_node->data();
  if (r.op == "subscribe") {
    const auto list = root.get_child_optional("subscriptions");
    if (!list || !list->data().empty()) return invalid("subscribe without a \"subscriptions\" list", r.op);
    for (const auto& [key, item] : *list) {
      Subscription s;
      const auto id = item.get_child_optional("id");
      const auto channel = item.get_child_optional("channelId");
      if (!key.empty() || !id || !channel || !read_id(*id, s.id) || !read_id(*channel, s.channel))
        return invalid("subscribe: each subscription needs an \"id\" and a \"channelId\" (integers, 0 .. 2^32-1)",
                       r.op);
      r.subscriptions.push_back(s);
    }
    r.kind = ClientRequest::Kind::subscribe;
    return r;
  }
  if (r.op == "unsubscribe") {
    const auto list = root.get_child_optional("subscriptionIds");
    if (!list || !list->data().empty()) return invalid("unsubscribe without a \"subscriptionIds\" list", r.op);
    for (const auto& [key, item] : *list) {
      std::uint32_t id = 0;
      if (!key.empty() || !read_id(item, id))
        return invalid("unsubscribe: \"subscriptionIds\" must be integers (0 .. 2^32-1)", r.op);
      r.subscription_ids.push_back(id);
    }
    r.kind = ClientRequest::Kind::unsubscribe;
    return r;
  }
  r.kind = ClientRequest::Kind::unsupported;
  return r;
}

}  // namespace hapticd::server::live_view
