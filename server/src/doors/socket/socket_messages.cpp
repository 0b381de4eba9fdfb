#include "doors/socket/socket_messages.hpp"

#include <algorithm>
#include <cmath>

#include "hapticd/dds/conversion.hpp"
#include "hapticd/json_text.hpp"

namespace hapticd::server::socket_messages {

using namespace json_text;
using Value = JsonReader::Value;
using Kind = JsonReader::Kind;

namespace {

struct RequestName {
  std::string_view name;
  hapticd_msg_RequestKind kind;
};
constexpr RequestName kRequests[] = {
    {"claim", hapticd_msg_REQUEST_CLAIM},
    {"release", hapticd_msg_REQUEST_RELEASE},
    {"switch_scheme", hapticd_msg_REQUEST_SWITCH_SCHEME},
    {"set_parameter", hapticd_msg_REQUEST_SET_PARAMETER},
    {"get_parameter", hapticd_msg_REQUEST_GET_PARAMETER},
    {"describe_parameter", hapticd_msg_REQUEST_DESCRIBE_PARAMETER},
    {"estop", hapticd_msg_REQUEST_ESTOP},
    {"recover", hapticd_msg_REQUEST_RECOVER},
    {"operator", hapticd_msg_REQUEST_OPERATOR},
    {"describe", hapticd_msg_REQUEST_DESCRIBE},
    {"group_claim", hapticd_msg_REQUEST_GROUP_CLAIM},
    {"group_release", hapticd_msg_REQUEST_GROUP_RELEASE},
    {"group_estop", hapticd_msg_REQUEST_GROUP_ESTOP},
    {"group_recover", hapticd_msg_REQUEST_GROUP_RECOVER},
};

// A number member (absent: `fallback`; present but not a number: false).
bool number(const Value& object, std::string_view key, double& out, double fallback = 0.0) {
  const Value v = object[key];
  if (!v) {
    out = fallback;
    return true;
  }
  const std::optional<double> n = v.number();
  if (!n) return false;
  out = *n;
  return true;
}

// {"x":..,"y":..,"z":..} into out[0..2] (absent: zeros).
bool vector3(const Value& v, double* out) {
  if (!v) {
    out[0] = out[1] = out[2] = 0.0;
    return true;
  }
  return v.kind() == Kind::object && number(v, "x", out[0]) && number(v, "y", out[1]) && number(v, "z", out[2]);
}

// {"w":..,"x":..,"y":..,"z":..} into out[0..3] (absent: identity).
bool quaternion(const Value& v, double* out) {
  if (!v) {
    out[0] = 1.0;
    out[1] = out[2] = out[3] = 0.0;
    return true;
  }
  return v.kind() == Kind::object && number(v, "w", out[0], 1.0) && number(v, "x", out[1]) && number(v, "y", out[2]) &&
         number(v, "z", out[3]);
}

// [a, b, c, d, e, f] into out[0..5] (absent: zeros).
bool vector6(const Value& v, double* out) {
  for (int i = 0; i < 6; ++i) out[i] = 0.0;
  if (!v) return true;
  if (v.kind() != Kind::array || v.size() != 6) return false;
  for (std::size_t i = 0; i < 6; ++i) {
    const std::optional<double> n = v.at(i).number();
    if (!n) return false;
    out[i] = *n;
  }
  return true;
}

// A name member that fits a DDS Name or Text (`capacity` characters).
bool text(const Value& object, std::string_view key, std::size_t capacity, std::string_view& out) {
  const Value v = object[key];
  if (!v) {
    out = {};
    return true;
  }
  const std::optional<std::string_view> s = v.string();
  if (!s || s->size() > capacity) return false;
  out = *s;
  return true;
}

// A pose and twist command ({"position", "orientation", "velocity", "angular_velocity"}).
bool pose_and_twist(const Value& v, hapticd_msg_EngineCommand& c) {
  return v.kind() == Kind::object && vector3(v["position"], c.command_pose.position) &&
         quaternion(v["orientation"], c.command_pose.orientation) && vector3(v["velocity"], c.twist) &&
         vector3(v["angular_velocity"], c.twist + 3);
}

// {"x":..,"y":..,"z":..} or {"w":..,...}: the named components of v.
template <std::size_t N>
void json_components(std::string& out, const char* const (&names)[N], const double* v) {
  for (std::size_t i = 0; i < N; ++i) {
    out += i == 0 ? "{\"" : ",\"";
    out += names[i];
    out += "\":";
    append_number(out, v[i]);
  }
  out += '}';
}
void json_vector3(std::string& out, const double* v) {
  static constexpr const char* kNames[] = {"x", "y", "z"};
  json_components(out, kNames, v);
}
void json_quaternion(std::string& out, const double* q) {
  static constexpr const char* kNames[] = {"w", "x", "y", "z"};
  json_components(out, kNames, q);
}
// ,"key":{...}
void append_vector3(std::string& out, std::string_view key, const double* v) {
  append_key(out, key);
  json_vector3(out, v);
}
void append_quaternion(std::string& out, std::string_view key, const double* q) {
  append_key(out, key);
  json_quaternion(out, q);
}
// One member of a JSON object: a comma before all but the first, then "key":.
void json_member(std::string& out, bool& first, std::string_view key) {
  if (!first) out += ',';
  first = false;
  append_string(out, key);
  out += ':';
}

// The state's and the event's members, the enums' names: generated from idl/hapticd_wire.toml.
#include "hapticd_wire/socket_json.inc"

}  // namespace

bool Parser::command(const Value& entry, std::string_view engine, std::uint64_t& serial, std::uint64_t state_serial,
                     ClientMessage& out) {
  std::string_view device;
  if (entry.kind() != Kind::object || !text(entry, "device_id", 31, device) || device.empty()) {
    out.error = "each device entry needs a device_id (a device name, at most 31 characters)";
    return false;
  }
  double answered = static_cast<double>(state_serial);
  if (!number(entry, "state_serial", answered, answered) || answered < 0.0) {
    out.error = "state_serial must be a number (the serial of the state the command answers)";
    return false;
  }
  const Value commands = entry["commands"];
  if (!commands) return true;  // an entry without commands (Haply's clients send some)
  if (commands.kind() != Kind::object || commands.size() != 1) {
    out.error = "a device's commands hold one of set_cursor_force, set_wrench, set_coupling, set_motion";
    return false;
  }
  if (out.commands.size() >= kMaxCommands) {
    out.error = "at most 8 device commands per message";
    return false;
  }
  hapticd_msg_EngineCommand c{};
  dds::set_text(c.device, device);
  dds::set_text(c.engine, engine);
  c.state_serial = static_cast<std::uint64_t>(answered);
  c.command_pose.orientation[0] = 1.0;
  c.anchor.orientation[0] = 1.0;
  bool ok = false;
  if (const Value f = commands["set_cursor_force"]) {  // Haply's: a force on the cursor
    c.kind = hapticd_msg_COMMAND_WRENCH;
    ok = f.kind() == Kind::object && vector3(f["vector"], c.wrench) && f["vector"];
  } else if (const Value w = commands["set_wrench"]) {
    c.kind = hapticd_msg_COMMAND_WRENCH;
    ok = w.kind() == Kind::object && vector3(w["force"], c.wrench) && vector3(w["torque"], c.wrench + 3);
    if (ok && (w["stiffness"] || w["damping"] || w["anchor"])) {  // a local model the server evaluates every cycle
      c.local_model = true;
      const Value anchor = w["anchor"];
      ok = vector6(w["stiffness"], c.stiffness) && vector6(w["damping"], c.damping) &&
           (!anchor || (anchor.kind() == Kind::object && vector3(anchor["position"], c.anchor.position) &&
                        quaternion(anchor["orientation"], c.anchor.orientation)));
    }
  } else if (const Value p = commands["set_coupling"]) {
    c.kind = hapticd_msg_COMMAND_COUPLING;
    ok = pose_and_twist(p, c);
  } else if (const Value m = commands["set_motion"]) {
    c.kind = hapticd_msg_COMMAND_MOTION;
    ok = pose_and_twist(m, c);
  } else {
    out.error = "unknown command (set_cursor_force, set_wrench, set_coupling and set_motion are offered)";
    return false;
  }
  if (!ok) {
    out.error =
        "malformed command for '" + std::string(device) + "': numbers expected where docs/engine-socket.md shows them";
    return false;
  }
  c.serial = ++serial;
  out.commands.push_back(c);
  return true;
}

bool Parser::request(const Value& r, std::string_view client, ClientMessage& out) {
  if (r.kind() != Kind::object) {
    out.error = "request: expected an object";
    return false;
  }
  std::string_view kind, device, name;
  double id = 0.0;
  if (!text(r, "kind", 31, kind) || !text(r, "device", 31, device) || !text(r, "name", 127, name) ||
      !number(r, "id", id) || id < 0.0 || id > 9007199254740992.0 || device.empty()) {
    out.error = "request: needs kind, device (a name), a numeric id and at most a name of 127 characters";
    return false;
  }
  hapticd_msg_ControlRequest m{};
  bool known = false;
  for (const RequestName& k : kRequests)
    if (k.name == kind) {
      m.kind = k.kind;
      known = true;
    }
  if (!known) {
    out.error =
        "request: unknown kind (claim, release, switch_scheme, set_parameter, get_parameter, "
        "describe_parameter, estop, recover, operator, describe, group_claim, group_release, group_estop, "
        "group_recover)";
    return false;
  }
  const Value values = r["values"];
  if (values && (values.kind() != Kind::array || values.size() > hapticd_msg_MAX_VALUES)) {
    out.error = "request: values must be a list of at most 16 numbers";
    return false;
  }
  for (std::size_t i = 0; i < values.size(); ++i) {
    const std::optional<double> v = values.at(i).number();
    if (!v) {
      out.error = "request: values must be numbers";
      return false;
    }
    m.values[i] = *v;
  }
  m.value_count = static_cast<std::int32_t>(values.size());
  dds::set_text(m.device, device);
  dds::set_text(m.client, client);
  dds::set_text(m.subject, name);
  m.request_id = static_cast<std::uint64_t>(id);
  out.request = m;
  return true;
}

namespace {
struct SceneOpName {
  std::string_view name;
  SceneGate::Op op;
};
constexpr SceneOpName kSceneOps[] = {
    {"claim", SceneGate::Op::claim},   {"release", SceneGate::Op::release},   {"add", SceneGate::Op::add},
    {"remove", SceneGate::Op::remove}, {"material", SceneGate::Op::material}, {"move", SceneGate::Op::move},
    {"list", SceneGate::Op::list},     {"contacts", SceneGate::Op::contacts}, {"upload", SceneGate::Op::upload},
    {"draw", SceneGate::Op::draw},
};
}  // namespace

bool Parser::scene(const Value& s, ClientMessage& out) {
  std::string_view op, name;
  double id = 0.0;
  if (s.kind() != Kind::object || !text(s, "op", 15, op) || !number(s, "id", id) || id < 0.0 ||
      id > 9007199254740992.0 || !text(s, "name", 64, name) || op.empty()) {
    out.error = "scene: needs op, a numeric id and at most a name of 64 characters";
    return false;
  }
  SceneMessage m;
  m.id = static_cast<std::int64_t>(id);
  const auto found =
      std::find_if(std::begin(kSceneOps), std::end(kSceneOps), [&](const auto& k) { return k.name == op; });
  if (found == std::end(kSceneOps)) {
    out.error = "scene: unknown op (claim, release, add, remove, material, move, list, contacts, upload, draw)";
    return false;
  }
  SceneGate::Edit& e = m.edit;
  e.op = found->op;
  e.name = name;
  const bool named = e.op == SceneGate::Op::remove || e.op == SceneGate::Op::material || e.op == SceneGate::Op::move;
  if (named && name.empty()) {
    out.error = "scene: " + std::string(op) + " needs the object's name";
    return false;
  }
  if (e.op == SceneGate::Op::add) {
    const std::optional<std::string_view> object = s["object"].source();
    if (!object || s["object"].kind() != Kind::object) {
      out.error = "scene: add needs the object ({\"name\": ..., \"shape\": ..., ...}: docs/haptic-scene.md)";
      return false;
    }
    e.text = *object;
    if (const Value upload = s["object"]["upload"]) {  // a mesh made of an upload
      const std::optional<std::string_view> u = upload.string();
      if (!u || u->empty() || u->size() > 64) {
        out.error = "scene: an object's upload is the name of an upload (1 to 64 characters)";
        return false;
      }
      e.upload = *u;
    }
  } else if (e.op == SceneGate::Op::upload) {
    const std::optional<std::string_view> u = s["upload"].string();
    const double part = s["part"].number_or(-1.0), parts = s["parts"].number_or(-1.0);
    const Value vertices = s["vertices"], triangles = s["triangles"];
    if (!u || u->empty() || u->size() > 64 || part < 0.0 || parts < 1.0 || part >= parts || parts > 1e6 ||
        std::floor(part) != part || std::floor(parts) != parts || vertices.kind() != Kind::array ||
        triangles.kind() != Kind::array) {
      out.error =
          "scene: upload needs its name (upload), part (from 0) of parts, and vertices and triangles "
          "(lists of numbers: x, y, z per vertex; three vertex indices per triangle)";
      return false;
    }
    e.upload = *u;
    e.part = static_cast<int>(part);
    e.parts = static_cast<int>(parts);
    out.scene_vertices.clear();
    out.scene_triangles.clear();
    for (Value x = vertices.first(); x; x = x.next()) {
      const std::optional<double> v = x.number();
      if (!v) {
        out.error = "scene: upload: vertices must be numbers";
        return false;
      }
      out.scene_vertices.push_back(*v);  // (not finite: the gate refuses the part)
    }
    for (Value x = triangles.first(); x; x = x.next()) {
      const std::optional<double> t = x.number();
      if (!t || *t < 0.0 || *t > 4294967295.0 || std::floor(*t) != *t) {
        out.error = "scene: upload: triangles must be vertex indices (whole numbers from 0)";
        return false;
      }
      out.scene_triangles.push_back(static_cast<std::uint32_t>(*t));
    }
    e.vertices = out.scene_vertices;
    e.triangles = out.scene_triangles;
  } else if (e.op == SceneGate::Op::draw) {
    const double most = s["max_triangles"].number_or(2000.0), first = s["first"].number_or(0.0);
    if (!(most >= 0.0 && most <= static_cast<double>(SceneGate::kMaxDrawTriangles) && std::floor(most) == most &&
          first >= 0.0 && first <= 1e9 && std::floor(first) == first)) {
      out.error = "scene: draw's max_triangles is a whole number to 20000 and its first one from 0";
      return false;
    }
    e.max_triangles = static_cast<std::size_t>(most);
    e.first = static_cast<std::size_t>(first);
  } else if (e.op == SceneGate::Op::material) {
    const Value material = s["material"];
    if (const std::optional<std::string_view> by_name = material.string(); by_name && by_name->size() <= 64) {
      out.scene_text = "\"" + std::string(*by_name) + "\"";  // a JSON string is a YAML double-quoted scalar
      e.text = out.scene_text;
    } else if (material.kind() == Kind::object) {
      e.text = *material.source();
    } else {
      out.error = "scene: material needs a material's name or a material ({\"stiffness\": ..., ...})";
      return false;
    }
  } else if (e.op == SceneGate::Op::move) {
    double p[3], q[4];
    if (!s["position"] || !vector3(s["position"], p) || !quaternion(s["orientation"], q)) {
      out.error = "scene: move needs a position {x, y, z} (and an orientation {w, x, y, z}, default none)";
      return false;
    }
    e.pose.position = Eigen::Vector3d(p[0], p[1], p[2]);
    e.pose.orientation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);  // checked by the scene (finite, not zero)
  }
  out.scene = m;
  return true;
}

bool Parser::parse(std::string_view text_in, std::string_view engine, std::uint64_t& serial, ClientMessage& out) {
  out.commands.clear();
  out.request.reset();
  out.scene.reset();
  out.scene_text.clear();
  out.scene_vertices.clear();
  out.scene_triangles.clear();
  out.subscribe.reset();
  out.profile.reset();
  out.error.clear();
  if (!json_.parse(text_in)) {
    out.error = std::string("not JSON: ") + json_.error();
    return false;
  }
  const Value root = json_.root();
  if (root.kind() != Kind::object) {
    out.error = "expected a JSON object";
    return false;
  }
  std::string_view client = engine;
  if (const Value session = root["session"]) {
    std::string_view name;
    const Value profile = session["configure"]["profile"];
    if (!profile || !text(profile, "name", 31, name) || name.empty()) {
      out.error = "session: expected {\"configure\":{\"profile\":{\"name\":\"<client id, 1-31 characters>\"}}}";
      return false;
    }
    out.profile = std::string(name);
    client = name;
  }
  if (const Value s = root["subscribe"]) {
    if (s.kind() != Kind::array || s.size() > 64) {
      out.error = "subscribe: expected a list of device names";
      return false;
    }
    out.subscribe.emplace();
    for (std::size_t i = 0; i < s.size(); ++i) {
      const std::optional<std::string_view> name = s.at(i).string();
      if (!name || name->empty() || name->size() > 31) {
        out.error = "subscribe: expected a list of device names";
        return false;
      }
      out.subscribe->emplace_back(*name);
    }
  }
  if (const Value r = root["request"]; r && !request(r, client, out)) return false;
  if (const Value s = root["scene"]; s && !scene(s, out)) return false;
  double state_serial = 0.0;
  if (!number(root, "state_serial", state_serial) || state_serial < 0.0) {
    out.error = "state_serial must be a number";
    return false;
  }
  Value devices = root["devices"];
  if (!devices) devices = root["inverse3"];  // a client written for Haply's Inverse Service
  if (devices) {
    if (devices.kind() != Kind::array) {
      out.error = "devices: expected a list";
      return false;
    }
    const std::uint64_t first_serial = serial;
    for (std::size_t i = 0; i < devices.size(); ++i)
      if (!command(devices.at(i), client, serial, static_cast<std::uint64_t>(state_serial), out)) {
        serial = first_serial;  // nothing of a malformed message applies
        out.commands.clear();
        return false;
      }
  }
  return true;
}

std::string inventory(std::uint64_t session_id, std::string_view client, const std::vector<InventoryDevice>& devices,
                      const std::vector<InventoryGroup>& groups) {
  std::string out = "{\"session_id\":";
  append_integer(out, static_cast<std::int64_t>(session_id));
  append_key(out, "client");
  append_string(out, client);
  out += ",\"devices\":[";
  for (std::size_t i = 0; i < devices.size(); ++i) {
    const InventoryDevice& d = devices[i];
    if (i > 0) out += ',';
    out += "{\"device_id\":";
    append_string(out, d.name);
    out += ",\"config\":{\"model\":";
    append_string(out, d.model);
    append_key(out, "interface");
    append_string(out, d.interface);
    append_key(out, "dof");
    append_integer(out, d.dof);
    out += d.simulated ? ",\"simulated\":true" : ",\"simulated\":false";
    append_key(out, "command_deadline_s");
    append_number(out, d.command_deadline_s);
    append_vector3(out, "base_position", d.base_position.data());
    append_quaternion(out, "base_orientation", d.base_orientation.data());
    append_key(out, "scheme");
    append_string(out, d.scheme);
    out += ",\"schemes\":[";
    for (std::size_t k = 0; k < d.schemes.size(); ++k) {
      if (k > 0) out += ',';
      append_string(out, d.schemes[k]);
    }
    out += "]}}";
  }
  out += "],\"groups\":[";
  for (std::size_t i = 0; i < groups.size(); ++i) {
    if (i > 0) out += ',';
    out += "{\"group_id\":";
    append_string(out, groups[i].name);
    out += ",\"devices\":[";
    for (std::size_t k = 0; k < groups[i].devices.size(); ++k) {
      if (k > 0) out += ',';
      append_string(out, groups[i].devices[k]);
    }
    out += "]}";
  }
  out += "]}";
  return out;
}

void state(const hapticd_msg_DeviceState& s, std::string& out) {
  out.clear();
  out += "{\"devices\":[{\"device_id\":";
  append_string(out, dds::text_of(s.device));
  out += ',';
  append_json(out, s);
  out += "}]}";
}

namespace {
// ,"key":[{...},{...}]: each item an object that `write` fills after its opening brace.
template <class T, class Write>
void append_objects(std::string& out, std::string_view key, const std::vector<T>& items, Write write) {
  append_key(out, key);
  out += '[';
  for (std::size_t i = 0; i < items.size(); ++i) {
    out += i > 0 ? ",{" : "{";
    write(items[i]);
    out += '}';
  }
  out += ']';
}
}  // namespace

namespace {
// ,"drawing":{"objects":[...],"proxies":[...]}: each object's shape, pose and size; a mesh's corners (three per
// triangle) as one list of numbers, in tenths of a millimetre (whole numbers: a third of the text of metres).
void append_drawing(std::string& out, const SceneDrawing& d, std::size_t drawn) {
  append_key(out, "drawing");
  out += "{\"objects\":[";
  for (std::size_t i = 0; i < d.objects.size(); ++i) {
    const SceneObjectDrawing& o = d.objects[i];
    out += i > 0 ? ",{\"name\":" : "{\"name\":";
    append_string(out, o.name);
    append_key(out, "shape");
    append_string(out, o.shape);
    out += o.moving ? ",\"moving\":true" : ",\"moving\":false";
    append_vector3(out, "position", o.pose.position.data());
    const double q[4] = {o.pose.orientation.w(), o.pose.orientation.x(), o.pose.orientation.y(),
                         o.pose.orientation.z()};
    append_quaternion(out, "orientation", q);
    append_vector3(out, "size", o.size.data());
    append_key(out, "triangles");
    append_integer(out, static_cast<std::int64_t>(o.triangles));
    if (o.shape == "mesh") {
      append_key(out, "drawn");
      append_integer(out, static_cast<std::int64_t>(drawn));
      out += ",\"corners_0_1mm\":[";
      for (std::size_t k = 0; k < o.corners.size(); ++k)
        for (int c = 0; c < 3; ++c) {
          if (k + c > 0) out += ',';
          append_integer(out, static_cast<std::int64_t>(std::lround(o.corners[k][c] * 1e4f)));
        }
      out += ']';
    }
    out += '}';
  }
  out += "],\"proxies\":[";
  for (std::size_t i = 0; i < d.proxies.size(); ++i) {
    const SceneProxyDrawing& p = d.proxies[i];
    out += i > 0 ? ",{\"device\":" : "{\"device\":";
    append_string(out, p.device);
    append_vector3(out, "position", p.position.data());
    append_key(out, "radius");
    append_number(out, p.radius);
    out += p.touching ? ",\"touching\":true}" : ",\"touching\":false}";
  }
  out += "]}";
}
}  // namespace

std::string scene_reply(std::int64_t id, const SceneGate::Reply& r) {
  std::string out = "{\"scene_reply\":{\"id\":";
  append_integer(out, id);
  out += r.accepted ? ",\"accepted\":true" : ",\"accepted\":false";
  append_key(out, "message");
  append_string(out, r.message);
  if (r.objects)  // an empty scene answers an empty list
    append_objects(out, "objects", *r.objects, [&](const SceneObjectSummary& o) {
      out += "\"name\":";
      append_string(out, o.name);
      append_key(out, "shape");
      append_string(out, o.shape);
      append_key(out, "uid");
      append_integer(out, static_cast<std::int64_t>(o.uid));
      out += o.moving ? ",\"moving\":true" : ",\"moving\":false";
      append_key(out, "triangles");
      append_integer(out, static_cast<std::int64_t>(o.triangles));
    });
  if (r.contacts)
    append_objects(out, "contacts", *r.contacts, [&](const SceneContact& c) {
      out += "\"device\":";
      append_string(out, c.device);
      append_key(out, "object");
      append_string(out, c.object);
      append_vector3(out, "force", c.force.data());
      append_vector3(out, "torque", c.torque.data());
      append_vector3(out, "point", c.point.data());
    });
  if (r.drawing) append_drawing(out, *r.drawing, r.drawn);
  out += "}}";
  return out;
}

std::string reply(std::int64_t id, const hapticd_msg_ControlReply& r) {
  std::string out = "{\"reply\":{\"id\":";
  append_integer(out, id);
  append_key(out, "device");
  append_string(out, dds::text_of(r.device));
  out += r.accepted ? ",\"accepted\":true" : ",\"accepted\":false";
  append_key(out, "message");
  append_string(out, dds::text_of(r.message));
  out += ",\"values\":[";
  for (std::int32_t i = 0; i < std::clamp<std::int32_t>(r.value_count, 0, hapticd_msg_MAX_VALUES); ++i) {
    if (i > 0) out += ',';
    append_number(out, r.values[i]);
  }
  out += "]}}";
  return out;
}

std::string_view event_kind_name(std::int32_t kind) {
  return kind >= hapticd_msg_EVENT_FAULT && kind <= hapticd_msg_EVENT_PARAMETER
             ? json_name(static_cast<hapticd_msg_EventKind>(kind))
             : "other";
}

std::string event(const hapticd_msg_Event& e) {
  std::string out = "{";
  append_json(out, e);
  out += '}';
  return out;
}

std::string error(std::string_view code, std::string_view message, std::uint64_t count) {
  std::string out = "{\"error\":{\"code\":";
  append_string(out, code);
  append_key(out, "message");
  append_string(out, message);
  append_key(out, "count");
  append_integer(out, static_cast<std::int64_t>(count));
  out += "}}";
  return out;
}

}  // namespace hapticd::server::socket_messages
