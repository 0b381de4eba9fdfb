#include "config/session_config.hpp"

#include <arpa/inet.h>

#include <algorithm>
#include <set>

#include "config/config_error.hpp"
#include "config/config_overrides.hpp"
#include "config/teleoperation_settings.hpp"
#include "config/yaml_document.hpp"
#include "config/yaml_reader.hpp"
#include "hapticd/input_file.hpp"
#include "net/websocket_server.hpp"

namespace hapticd::server {
namespace {

// A plugin entry ({plugin, library, parameters}); `plugin` may be left out when there is a default_plugin.
PluginConfig read_plugin(const YAML::Node& node, const std::string& key_path, const std::string& file,
                         const char* default_plugin = nullptr) {
  MappingReader reader(node, key_path, file, {"plugin", "library", "parameters"});
  PluginConfig plugin;
  plugin.key_path = key_path;
  plugin.line = line_of(node);
  plugin.plugin = default_plugin != nullptr && !reader.optional("plugin").IsDefined()
                      ? std::string(default_plugin)
                      : reader.required_string("plugin");
  const YAML::Node library = reader.optional("library");
  if (library.IsDefined() && !library.IsNull()) {
    if (!library.IsScalar())
      throw ConfigError(file, line_of(library), reader.path_of("library"), "expected a library name or path");
    plugin.library = library.Scalar();
  }
  plugin.parameters = reader.optional("parameters");
  return plugin;
}

std::optional<PluginConfig> read_optional_plugin(MappingReader& reader, const std::string& key) {
  const YAML::Node node = reader.optional(key);
  if (!node.IsDefined() || node.IsNull()) return std::nullopt;
  return read_plugin(node, reader.path_of(key), reader.file());
}

double read_scalar_real(const YAML::Node& node, const std::string& key_path, const std::string& file, double min,
                        double max) {
  double v = 0.0;
  try {
    v = node.as<double>();
  } catch (const YAML::Exception&) {
    throw ConfigError(file, line_of(node), key_path, "expected a number");
  }
  if (!(v >= min && v <= max)) {
    throw ConfigError(file, line_of(node), key_path,
                      "value " + node.Scalar() + " is outside " + std::to_string(min) + " .. " + std::to_string(max));
  }
  return v;
}

// The alternative schemes of a device: a list of {name, virtual_model?, inverse_kinematics?, controller}.
void read_schemes(MappingReader& reader, DeviceConfig& device) {
  const std::string& file = reader.file();
  if (const YAML::Node ramp = reader.optional("switch_ramp_s"); ramp.IsDefined()) {
    device.switch_ramp_s = read_scalar_real(ramp, reader.path_of("switch_ramp_s"), file, 0.0, 5.0);
  }
  const YAML::Node list = reader.optional("schemes");
  if (!list.IsDefined() || list.IsNull()) return;
  if (!list.IsSequence())
    throw ConfigError(file, line_of(list), reader.path_of("schemes"), "expected a list of schemes");
  std::set<std::string> names{device.scheme};
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string path = reader.path_of("schemes") + "[" + std::to_string(k) + "]";
    MappingReader r(list[k], path, file, {"name", "virtual_model", "inverse_kinematics", "controller"});
    SchemeConfig scheme;
    scheme.name = r.required_string("name");
    if (!names.insert(scheme.name).second)
      throw ConfigError(file, line_of(list[k]["name"]), r.path_of("name"),
                        "scheme name '" + scheme.name + "' is used twice");
    scheme.virtual_model = read_optional_plugin(r, "virtual_model");
    scheme.inverse_kinematics = read_optional_plugin(r, "inverse_kinematics");
    scheme.controller = read_plugin(r.required("controller"), r.path_of("controller"), file);
    device.alternatives.push_back(std::move(scheme));
  }
}

bool valid_device_name(const std::string& name) {
  if (name.empty() || name.size() > 31) return false;  // the DDS key holds 31 characters
  for (char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) return false;
  return true;
}

ServerSettings read_server(const YAML::Node& node, const std::string& file, const std::filesystem::path& base) {
  ServerSettings settings;
  if (!node.IsDefined() || node.IsNull()) return settings;
  if (!node.IsMap()) throw ConfigError(file, line_of(node), "server", "expected a mapping of server settings");

  // plugin_paths is a list of strings, read apart from the schema'd scalar settings.
  if (const YAML::Node paths = node["plugin_paths"]; paths.IsDefined() && !paths.IsNull()) {
    if (!paths.IsSequence())
      throw ConfigError(file, line_of(paths), "server.plugin_paths", "expected a list of folders");
    for (std::size_t i = 0; i < paths.size(); ++i) {
      if (!paths[i].IsScalar())
        throw ConfigError(file, line_of(paths[i]), "server.plugin_paths[" + std::to_string(i) + "]",
                          "expected a folder path");
      std::filesystem::path p = paths[i].Scalar();
      settings.plugin_paths.push_back(p.is_absolute() ? p : base / p);
    }
  }

  const Parameters p = read_parameters(node, server_settings_schema(), file, "server", line_of(node), {"plugin_paths"});
  settings.rate_hz = p.real("rate_hz");
  settings.clock = clock_mode(p.string("clock"));
  settings.clock_device = p.string("clock_device");
  if (const YAML::Node c = node["clock"]; c.IsDefined()) settings.clock_line = line_of(c);
  if (!settings.clock_device.empty() && settings.clock != ClockMode::device)
    throw ConfigError(file, line_of(node["clock_device"]), "server.clock_device",
                      "names the device that clocks the loop, which only `clock: device` uses");
  settings.duration_s = p.real("duration_s");
  settings.seed = static_cast<std::uint64_t>(p.integer("seed"));
  settings.realtime_priority = static_cast<int>(p.integer("realtime_priority"));
  settings.lock_memory = p.boolean("lock_memory");
  settings.cpu = static_cast<int>(p.integer("cpu"));
  settings.cpu_dma_latency_us = static_cast<int>(p.integer("cpu_dma_latency_us"));
  settings.shutdown_ramp_s = p.real("shutdown_ramp_s");
  return settings;
}

// `dds.network`: {interfaces: [names or addresses], peers: [addresses], multicast: false}.
dds::NetworkSettings read_network(const YAML::Node& node, const std::string& file) {
  if (!node.IsMap())
    throw ConfigError(file, line_of(node), "dds.network", "expected a mapping: interfaces, peers, multicast");
  MappingReader r(node, "dds.network", file, {"interfaces", "peers", "multicast"});
  dds::NetworkSettings n;
  const auto names = [&](const std::string& key, std::vector<std::string>& out) {
    const YAML::Node list = r.optional(key);
    if (!list.IsDefined()) return;
    if (!list.IsSequence())
      throw ConfigError(file, line_of(list), r.path_of(key), "expected a list of interface names or addresses");
    for (std::size_t i = 0; i < list.size(); ++i) {
      if (!list[i].IsScalar())
        throw ConfigError(file, line_of(list[i]), r.path_of(key) + "[" + std::to_string(i) + "]",
                          "expected a name or address");
      out.push_back(list[i].Scalar());
    }
  };
  names("interfaces", n.interfaces);
  names("peers", n.peers);
  if (const YAML::Node m = r.optional("multicast"); m.IsDefined()) {
    bool value = false;
    if (!m.IsScalar() || !YAML::convert<bool>::decode(m, value))
      throw ConfigError(file, line_of(m), r.path_of("multicast"), "expected true or false");
    n.multicast = value;
  }
  try {
    dds::validate(n);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(file, line_of(node), "dds.network", e.what());
  }
  return n;
}

DdsSettings read_dds(const YAML::Node& node, const std::string& file, const std::filesystem::path& base) {
  DdsSettings d;
  if (!node.IsDefined()) return d;
  d.enabled = true;
  if (node.IsNull()) return d;  // `dds:` alone: on with the defaults
  if (!node.IsMap()) throw ConfigError(file, line_of(node), "dds", "expected a mapping of DDS settings");
  std::vector<std::string> elsewhere = gate_settings_schema().names();  // read by read_gate
  elsewhere.push_back("network");
  const Parameters p = read_parameters(node, dds_settings_schema(), file, "dds", line_of(node), elsewhere);
  d.enabled = p.boolean("enabled");
  d.domain_id = static_cast<int>(p.integer("domain_id"));
  if (const std::string c = p.string("cyclone_config"); !c.empty()) {
    const std::filesystem::path cp = c;
    d.cyclone_config = cp.is_absolute() ? cp : base / cp;
    if (!std::filesystem::exists(d.cyclone_config))
      throw ConfigError(file, line_of(node["cyclone_config"]), "dds.cyclone_config",
                        "no such file: " + d.cyclone_config.string());
  }
  if (node["network"].IsDefined()) {
    if (!d.cyclone_config.empty())
      throw ConfigError(file, line_of(node["network"]), "dds.network",
                        "give either dds.network or dds.cyclone_config, not both");
    d.network = read_network(node["network"], file);
  }
  d.cpu = static_cast<int>(p.integer("cpu"));
  d.max_peers = static_cast<int>(p.integer("max_peers"));
  d.log_lines_per_s = p.real("log_lines_per_s");
  return d;
}

GateSettings gate_settings_of(const Parameters& p) {
  GateSettings g;
  g.state_rate_hz = p.real("state_rate_hz");
  g.telemetry_rate_hz = p.real("telemetry_rate_hz");
  g.max_sample_age_s = p.real("max_sample_age_s");
  g.max_force_n = p.real("max_force_n");
  g.max_torque_nm = p.real("max_torque_nm");
  g.max_stiffness_n_per_m = p.real("max_stiffness_n_per_m");
  g.max_rotational_stiffness_n_m_per_rad = p.real("max_rotational_stiffness_n_m_per_rad");
  g.max_damping_n_s_per_m = p.real("max_damping_n_s_per_m");
  g.max_rotational_damping_n_m_s = p.real("max_rotational_damping_n_m_s");
  g.max_distance_m = p.real("max_distance_m");
  g.max_speed_m_s = p.real("max_speed_m_s");
  g.max_angular_speed_rad_s = p.real("max_angular_speed_rad_s");
  g.lockstep_sync = p.boolean("lockstep_sync");
  g.lockstep_wait_s = p.real("lockstep_wait_s");
  g.lockstep_start_wait_s = p.real("lockstep_start_wait_s");
  g.lockstep_start_every = p.string("lockstep_start_for") == "every";
  g.claim_grace_s = p.real("claim_grace_s");
  g.claim_hold_s = p.real("claim_hold_s");
  g.tuning_by_anyone = p.string("tuning_by") == "anyone";
  return g;
}

// The gate's settings: the `gate` section's keys, over those the `dds` section gives (sessions written before the
// gate had a section of its own) - a key in both is an error.
GateSettings read_gate(const YAML::Node& gate, const YAML::Node& dds, const std::string& file) {
  GateSettings base;
  const ParameterSchema schema = gate_settings_schema();
  if (dds.IsDefined() && dds.IsMap()) {  // the gate's keys of the dds section (its own are read by read_dds)
    std::vector<std::string> dds_keys = dds_settings_schema().names();
    dds_keys.push_back("network");
    base = gate_settings_of(read_parameters(dds, schema, file, "dds", line_of(dds), dds_keys));
  }
  if (!gate.IsDefined() || gate.IsNull()) return base;
  if (!gate.IsMap()) throw ConfigError(file, line_of(gate), "gate", "expected a mapping of the gate's settings");
  if (dds.IsDefined() && dds.IsMap())
    for (const auto& entry : gate) {
      const std::string key = entry.first.Scalar();
      if (dds[key].IsDefined())
        throw ConfigError(file, line_of(dds[key]), "dds." + key,
                          "also given in the gate section (gate." + key + "): give it once, there");
    }
  return gate_settings_of(read_parameters(gate, gate_settings_schema(base), file, "gate", line_of(gate)));
}

// A section's allowed_origins: web pages (their Origin) that may connect besides those served from this machine.
std::vector<std::string> read_origins(const YAML::Node& list, const std::string& file, const std::string& key) {
  std::vector<std::string> origins;
  if (!list.IsDefined() || list.IsNull()) return origins;
  if (!list.IsSequence() || list.size() > 16)
    throw ConfigError(file, line_of(list), key, "expected a list of at most 16 origins, e.g. [\"https://host:8443\"]");
  for (std::size_t i = 0; i < list.size(); ++i) {
    if (!list[i].IsScalar() || list[i].Scalar().find("://") == std::string::npos || list[i].Scalar().size() > 200)
      throw ConfigError(file, line_of(list[i]), key + "[" + std::to_string(i) + "]",
                        "expected an origin: scheme://host[:port]");
    origins.push_back(list[i].Scalar());
  }
  return origins;
}

void check_ip_address(const std::string& address, const YAML::Node& node, const std::string& file,
                      const std::string& key) {
  unsigned char parsed[sizeof(in6_addr)];
  if (inet_pton(AF_INET, address.c_str(), parsed) != 1 && inet_pton(AF_INET6, address.c_str(), parsed) != 1)
    throw ConfigError(file, line_of(node), key,
                      "'" + address + "' is not an IP address (127.0.0.1 for this machine only, the default)");
}

// The `scene` section: a plugin entry whose plugin is session_scene unless it names another; `scene:` alone is an
// empty scene the engines fill.
std::optional<PluginConfig> read_scene(const YAML::Node& node, const std::string& file) {
  if (!node.IsDefined()) return std::nullopt;
  PluginConfig scene;
  scene.plugin = "session_scene";
  scene.key_path = "scene";
  scene.line = line_of(node);
  if (node.IsNull()) return scene;
  return read_plugin(node, "scene", file, "session_scene");
}

LiveViewSettings read_live_view(const YAML::Node& node, const std::string& file) {
  LiveViewSettings v;
  if (!node.IsDefined()) return v;
  v.enabled = true;
  if (node.IsNull()) return v;  // `live_view:` alone: on with the defaults
  if (!node.IsMap()) throw ConfigError(file, line_of(node), "live_view", "expected a mapping of live view settings");
  const Parameters p =
      read_parameters(node, live_view_settings_schema(), file, "live_view", line_of(node), {"allowed_origins"});
  v.allowed_origins = read_origins(node["allowed_origins"], file, "live_view.allowed_origins");
  v.enabled = p.boolean("enabled");
  v.address = p.string("address");
  v.port = static_cast<int>(p.integer("port"));
  v.rate_hz = p.real("rate_hz");
  v.max_clients = static_cast<int>(p.integer("max_clients"));
  v.force_scale_m_per_n = p.real("force_scale_m_per_n");
  check_ip_address(v.address, node["address"], file, "live_view.address");
  return v;
}

EngineSocketSettings read_engine_socket(const YAML::Node& node, const std::string& file,
                                        const std::filesystem::path& folder) {
  EngineSocketSettings v;
  if (!node.IsDefined()) return v;
  v.enabled = true;
  if (node.IsNull()) return v;  // `engine_socket:` alone: on with the defaults
  if (!node.IsMap())
    throw ConfigError(file, line_of(node), "engine_socket", "expected a mapping of engine socket settings");
  const Parameters p =
      read_parameters(node, engine_socket_settings_schema(), file, "engine_socket", line_of(node), {"allowed_origins"});
  v.allowed_origins = read_origins(node["allowed_origins"], file, "engine_socket.allowed_origins");
  v.enabled = p.boolean("enabled");
  v.address = p.string("address");
  v.port = static_cast<int>(p.integer("port"));
  v.max_clients = static_cast<int>(p.integer("max_clients"));
  v.max_messages_per_s = p.real("max_messages_per_s");
  check_ip_address(v.address, node["address"], file, "engine_socket.address");
  if (const std::string token_file = p.string("token_file"); !token_file.empty()) {
    const std::filesystem::path path =
        std::filesystem::path(token_file).is_absolute() ? std::filesystem::path(token_file) : folder / token_file;
    std::string token;
    try {  // a regular file of at most 4 KiB: a named pipe or a device there is refused, never waited on
      token = read_input_file(path, "token file", 4096);
    } catch (const std::runtime_error& e) {
      throw ConfigError(file, line_of(node["token_file"]), "engine_socket.token_file", e.what());
    }
    token = token.substr(0, token.find('\n'));
    while (!token.empty() && (token.back() == '\r' || token.back() == ' ')) token.pop_back();
    if (token.size() < 16 || token.size() > 256 ||
        token.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-._~") !=
            std::string::npos)
      throw ConfigError(file, line_of(node["token_file"]), "engine_socket.token_file",
                        "the token in '" + path.string() +
                            "' must be 16-256 characters of letters, digits and -._~ (e.g. openssl rand -hex 24)");
    v.token = token;
  }
  const auto resolved = [&](const std::string& name) {
    const std::filesystem::path given = p.string(name);
    if (given.empty()) return given;
    const std::filesystem::path path = given.is_absolute() ? given : folder / given;
    try {  // OpenSSL reads it later: a regular file of at most 1 MiB, checked here
      (void)read_input_file(path, "PEM file", 1024u * 1024u);
    } catch (const std::runtime_error& e) {
      throw ConfigError(file, line_of(node[name]), "engine_socket." + name, e.what());
    }
    return path;
  };
  v.tls_certificate_file = resolved("tls_certificate_file");
  v.tls_private_key_file = resolved("tls_private_key_file");
  if (v.tls_certificate_file.empty() != v.tls_private_key_file.empty())
    throw ConfigError(file, line_of(node), "engine_socket",
                      "TLS needs both tls_certificate_file and tls_private_key_file (PEM files)");
  if (v.enabled && !net::loopback_address(v.address) && v.token.empty())
    throw ConfigError(file, line_of(node["address"]), "engine_socket.address",
                      "the engine socket listens beyond this machine only with a token: give engine_socket.token_file "
                      "(anyone who reaches " +
                          v.address + " could otherwise claim and drive the devices)");
  return v;
}

SafetySettings read_safety(const YAML::Node& node, const std::string& file, const std::string& key_path,
                           std::vector<std::string>& warnings) {
  if (node.IsDefined() && !node.IsNull() && !node.IsMap())
    throw ConfigError(file, line_of(node), key_path, "expected a mapping of safety settings");
  const ParameterSchema schema = safety_settings_schema();
  const Parameters p = read_parameters(node, schema, file, key_path, line_of(node), {});
  for (const ParameterSpec& spec : schema.specs()) {  // a safety function turned off is said at start-up
    if (!spec.can_be_off) continue;
    const ParameterValue& v = p.value(spec.name);
    const bool off = std::holds_alternative<double>(v) ? std::get<double>(v) == 0.0 : std::get<std::int64_t>(v) == 0;
    if (off) warnings.push_back(key_path + "." + spec.name + " is off (" + p.origin(spec.name) + ")");
  }
  try {
    return safety_settings_from(p);
  } catch (const ParameterError& e) {
    const std::string origin = p.origin(e.key());
    const auto colon = origin.rfind(':');
    const int line = colon == std::string::npos ? line_of(node) : std::atoi(origin.c_str() + colon + 1);
    throw ConfigError(file, line, key_path + "." + e.key(), e.what());
  }
}

Pose read_base_pose(const YAML::Node& node, const std::string& file, const std::string& key_path) {
  if (node.IsDefined() && !node.IsNull() && !node.IsMap())
    throw ConfigError(file, line_of(node), key_path, "expected a mapping {xyz: [x, y, z], rpy: [roll, pitch, yaw]}");
  const Parameters p = read_parameters(node, base_pose_schema(), file, key_path, line_of(node), {});
  const auto& xyz = p.real_vector("xyz");
  const auto& rpy = p.real_vector("rpy");
  Pose pose;
  pose.position = Eigen::Vector3d(xyz[0], xyz[1], xyz[2]);
  pose.orientation = Eigen::AngleAxisd(rpy[2], Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(rpy[1], Eigen::Vector3d::UnitY()) *
                     Eigen::AngleAxisd(rpy[0], Eigen::Vector3d::UnitX());
  return pose;
}

Eigen::Vector3d vector3(const std::vector<double>& v) { return Eigen::Vector3d(v[0], v[1], v[2]); }

ParameterSchema capsule_schema() {
  ParameterSchema s;
  s.string("link", "the URDF link the capsule moves with");
  s.real_vector("from", "one end of the capsule's segment, in the link's frame").unit("m").size(3);
  s.real_vector("to", "the other end").unit("m").size(3);
  s.real("radius_m", "the capsule's radius").unit("m").minimum(0.0);
  return s;
}

CollisionConfig read_collision(const YAML::Node& node, const std::string& file, const std::string& key_path) {
  CollisionConfig c;
  if (!node.IsDefined() || node.IsNull()) return c;
  MappingReader reader(node, key_path, file, {"capsules", "skeleton_radius_m"});
  if (const YAML::Node r = reader.optional("skeleton_radius_m"); r.IsDefined())
    c.skeleton_radius_m = read_scalar_real(r, reader.path_of("skeleton_radius_m"), file, 0.0, 1.0);
  const YAML::Node list = reader.optional("capsules");
  if (!list.IsDefined() || list.IsNull()) return c;
  if (!list.IsSequence())
    throw ConfigError(file, line_of(list), reader.path_of("capsules"),
                      "expected a list of {link, from: [x, y, z], to: [x, y, z], radius_m}");
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string path = reader.path_of("capsules") + "[" + std::to_string(k) + "]";
    const Parameters p = read_parameters(list[k], capsule_schema(), file, path, line_of(list[k]), {});
    c.capsules.push_back(CapsuleConfig{p.string("link"), vector3(p.real_vector("from")), vector3(p.real_vector("to")),
                                       p.real("radius_m"), path, line_of(list[k])});
  }
  return c;
}

std::vector<GroupConfig> read_groups(const YAML::Node& node, const std::string& file,
                                     const std::vector<DeviceConfig>& devices) {
  std::vector<GroupConfig> groups;
  if (!node.IsDefined() || node.IsNull()) return groups;
  if (!node.IsSequence())
    throw ConfigError(file, line_of(node), "groups", "expected a list of {name, devices: [...], min_distance_m}");
  std::set<std::string> names, grouped;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string path = "groups[" + std::to_string(i) + "]";
    MappingReader r(node[i], path, file, {"name", "devices", "min_distance_m", "repulsion", "loop", "model"});
    GroupConfig g;
    g.key_path = path;
    g.line = line_of(node[i]);
    g.name = r.required_string("name");
    if (!valid_device_name(g.name))
      throw ConfigError(file, line_of(node[i]["name"]), r.path_of("name"),
                        "group name '" + g.name + "' must be 1-31 characters of letters, digits, '_' and '-'");
    if (!names.insert(g.name).second)
      throw ConfigError(file, line_of(node[i]["name"]), r.path_of("name"), "group name '" + g.name + "' is used twice");
    if (std::any_of(devices.begin(), devices.end(), [&](const DeviceConfig& d) { return d.name == g.name; }))
      throw ConfigError(file, line_of(node[i]["name"]), r.path_of("name"),
                        "group name '" + g.name + "' is a device's name (requests name either)");
    const YAML::Node list = r.required("devices");
    if (!list.IsSequence() || list.size() == 0)
      throw ConfigError(file, line_of(list), r.path_of("devices"), "expected a non-empty list of device names");
    if (list.size() > 8)
      throw ConfigError(file, line_of(list), r.path_of("devices"),
                        "a group holds at most 8 devices (it has " + std::to_string(list.size()) + ")");
    for (std::size_t k = 0; k < list.size(); ++k) {
      const std::string where = r.path_of("devices") + "[" + std::to_string(k) + "]";
      if (!list[k].IsScalar()) throw ConfigError(file, line_of(list[k]), where, "expected a device name");
      const std::string name = list[k].Scalar();
      const bool known =
          std::any_of(devices.begin(), devices.end(), [&](const DeviceConfig& d) { return d.name == name; });
      if (!known) throw ConfigError(file, line_of(list[k]), where, "no device '" + name + "' in this session");
      if (!grouped.insert(name).second)
        throw ConfigError(file, line_of(list[k]), where, "device '" + name + "' is in a group already");
      g.devices.push_back(name);
    }
    if (const YAML::Node m = r.optional("min_distance_m"); m.IsDefined())
      g.min_distance_m = read_scalar_real(m, r.path_of("min_distance_m"), file, 0.0, 1.0);
    if (const YAML::Node rep = r.optional("repulsion"); rep.IsDefined() && !rep.IsNull()) {
      if (!rep.IsMap()) throw ConfigError(file, line_of(rep), r.path_of("repulsion"), "expected a mapping");
      const Parameters p = read_parameters(rep, repulsion_schema(), file, r.path_of("repulsion"), line_of(rep), {});
      g.repulsion = RepulsionSettings{p.real("distance_m"), p.real("stiffness_n_per_m"), p.real("damping_n_s_per_m"),
                                      p.real("max_force_n"), p.real("filter_hz")};
      if (g.repulsion.distance_m > 0.0 && g.repulsion.distance_m <= g.min_distance_m)
        throw ConfigError(file, line_of(rep["distance_m"]), r.path_of("repulsion") + ".distance_m",
                          "the repulsion must start farther out than the hard minimum (min_distance_m " +
                              format_value(g.min_distance_m) + ")");
    }
    if (const YAML::Node loop = r.optional("loop"); loop.IsDefined()) {
      if (!loop.IsNull() && !loop.IsMap())
        throw ConfigError(file, line_of(loop), r.path_of("loop"),
                          "expected a mapping ({cpu: N}, or {} for no pinning)");
      const Parameters p = read_parameters(loop.IsNull() ? YAML::Node(YAML::NodeType::Map) : loop, group_loop_schema(),
                                           file, r.path_of("loop"), line_of(loop), {});
      g.own_loop = true;
      g.loop_cpu = static_cast<int>(p.integer("cpu"));
    }
    if (const YAML::Node model = r.optional("model"); model.IsDefined() && !model.IsNull())
      g.model = read_plugin(model, r.path_of("model"), file);
    groups.push_back(std::move(g));
  }
  return groups;
}

}  // namespace

const std::vector<EntryKey>& device_entry_keys() {
  static const std::vector<EntryKey> keys{
      {"name", "the device's name (1-31 letters, digits, '_', '-'), unique in the session; its DDS key"},
      {"device", "the device plugin: {plugin: NAME, library: FILE (optional), parameters: {...}}"},
      {"virtual_model", "the starting scheme's virtual model plugin (optional), as for device"},
      {"inverse_kinematics", "the starting scheme's inverse kinematics plugin (optional), as for device"},
      {"controller", "the starting scheme's controller plugin, as for device"},
      {"scheme", "the starting scheme's name (default \"default\")"},
      {"schemes",
       "schemes to switch to at run time: a list of {name, virtual_model?, inverse_kinematics?, controller}"},
      {"switch_ramp_s",
       "a torque difference at a scheme switch (or after a recovery) fades out over this time, s "
       "(0 .. 5, default 0.1)"},
      {"engine_deadline_s", "engine input older than this fades out, s (0.001 .. 10, default 0.05)"},
      {"engine_fade_s", "... over this time, s (0 .. 10, default 0.02)"},
      {"engine_ramp_in_s", "engine input starting after a silence ramps in over this time, s (0 .. 10, default 0.1)"},
      {"base_pose",
       "where the device stands in the session's world frame: {xyz: [x, y, z] in m, rpy: [roll, pitch, yaw] in "
       "rad about the fixed axes, as a URDF origin}; default the origin"},
      {"collision",
       "the device's collision geometry: {capsules: [{link, from: [x, y, z], to: [x, y, z], radius_m}] in the "
       "link's frame (replacing the URDF's <collision> elements), skeleton_radius_m: radius of the capsules along "
       "the joints when neither gives any (0 .. 1, default 0.03)}"},
      {"safety", "the device's safety section (below)"},
  };
  return keys;
}

// `base_pose: {xyz: [x, y, z], rpy: [roll, pitch, yaw]}`, as a URDF <origin>: metres, and radians about the
// fixed x, y, z axes (R = Rz(yaw) Ry(pitch) Rx(roll)).
ParameterSchema base_pose_schema() {
  ParameterSchema s;
  s.real_vector("xyz", "position of the device's base in the world frame")
      .unit("m")
      .size(3)
      .default_value(std::vector<double>{0.0, 0.0, 0.0});
  s.real_vector("rpy", "orientation of the base: roll, pitch, yaw about the world's fixed x, y, z axes")
      .unit("rad")
      .size(3)
      .default_value(std::vector<double>{0.0, 0.0, 0.0});
  return s;
}

ParameterSchema repulsion_schema() {
  ParameterSchema s;
  const RepulsionSettings d;
  s.real("distance_m", "clearance below which the arms are pushed apart (0: no repulsion)")
      .unit("m")
      .minimum(0.0)
      .maximum(1.0)
      .default_value(d.distance_m);
  s.real("stiffness_n_per_m", "spring of the repulsion, on the nearest points")
      .unit("N/m")
      .minimum(0.0)
      .maximum(1e5)
      .default_value(d.stiffness_n_per_m);
  s.real("damping_n_s_per_m", "damping of the approach speed, on the nearest points")
      .unit("N s/m")
      .minimum(0.0)
      .maximum(1e3)
      .default_value(d.damping_n_s_per_m);
  s.real("max_force_n", "the largest repulsive force on each handle")
      .unit("N")
      .minimum(0.0)
      .maximum(200.0)
      .default_value(d.max_force_n);
  s.real("filter_hz",
         "low-pass of the repulsion's joint torques, first order (0: none): smooths the jump of the closest "
         "points along two nearly parallel links")
      .unit("Hz")
      .minimum(0.0)
      .maximum(1000.0)
      .default_value(d.filter_hz);
  return s;
}

ParameterSchema group_loop_schema() {
  ParameterSchema s;
  s.integer("cpu", "pin the group's loop thread to this CPU; -1 does not pin")
      .minimum(-1)
      .maximum(1023)
      .default_value(std::int64_t{-1});
  return s;
}

namespace {

// What every listening section has: on, the address and port, and how many clients at once.
ParameterSchema listener_schema(const char* what, const std::string& address, int port, const char* beyond_loopback,
                                const char* clients, int max_clients) {
  ParameterSchema s;
  s.boolean("enabled", std::string("serve the ") + what).default_value(true);
  s.string("address", std::string("IP address to listen on: 127.0.0.1 (the default) serves this machine only; another "
                                  "interface's address ") +
                          beyond_loopback)
      .default_value(address);
  s.integer("port", "TCP port; 0 takes any free port (the log names it)")
      .minimum(0)
      .maximum(65535)
      .default_value(std::int64_t{port});
  s.integer("max_clients", std::string(clients) + " connected at once (more are refused)")
      .minimum(1)
      .maximum(64)
      .default_value(std::int64_t{max_clients});
  return s;
}

}  // namespace

ParameterSchema engine_socket_settings_schema() {
  const EngineSocketSettings d;
  ParameterSchema s = listener_schema("engine socket", d.address, d.port, "needs token_file", "clients", d.max_clients);
  s.string("token_file",
           "a file holding the access token clients present (?token=... or Authorization: Bearer); relative to "
           "the session file; \"\": none (loopback only)")
      .default_value(std::string());
  s.string("tls_certificate_file",
           "TLS (wss://): the server's certificate chain, a PEM file relative to the session file; \"\": no TLS")
      .default_value(std::string());
  s.string("tls_private_key_file", "TLS: the certificate's private key, a PEM file").default_value(std::string());
  s.real("max_messages_per_s", "messages a client may send per second (more are dropped and counted)")
      .unit("1/s")
      .minimum(10.0)
      .maximum(100000.0)
      .default_value(d.max_messages_per_s);
  return s;
}

ParameterSchema live_view_settings_schema() {
  const LiveViewSettings d;
  ParameterSchema s = listener_schema("live view", d.address, d.port, "lets anyone who reaches it watch the session",
                                      "viewers", d.max_clients);
  s.real("rate_hz", "messages per channel and second").unit("Hz").minimum(1.0).maximum(200.0).default_value(d.rate_hz);
  s.real("force_scale_m_per_n", "length of a force arrow in the 3-D view per newton")
      .unit("m/N")
      .greater_than(0.0)
      .maximum(1.0)
      .default_value(d.force_scale_m_per_n);
  return s;
}

ParameterSchema dds_settings_schema() {
  ParameterSchema s;
  const DdsSettings d;
  s.boolean("enabled", "run the DDS interface").default_value(true);
  s.integer("domain_id", "DDS domain").minimum(0).maximum(230).default_value(std::int64_t{0});
  s.string("cyclone_config",
           "Cyclone DDS XML file; empty: dds.network (a mapping - interfaces, peers, multicast - not with this "
           "file; docs/deployment.md), else HAPTICD_DDS_CONFIG or HAPTICD_DDS_NETWORK, else the built-in "
           "loopback-only configuration (config/dds/cyclonedds-loopback.xml)")
      .default_value(std::string());
  s.integer("cpu",
            "CPU of the DDS threads: -2 auto (real-time clock, 2 or more CPUs: the loop on the last CPU "
            "unless server.cpu is set, the DDS threads on the others), -1 no pinning")
      .minimum(-2)
      .maximum(1023)
      .default_value(std::int64_t{d.cpu});
  s.integer("max_peers",
            "DDS writers whose participant the server remembers for ownership checks (least recently "
            "used first out), and writers remembered as having lost their liveliness")
      .minimum(8)
      .maximum(65536)
      .default_value(std::int64_t{d.max_peers});
  s.real("log_lines_per_s",
         "Cyclone DDS's own log lines (e.g. warnings about malformed packets) pass through the "
         "server's log at most this often, in bursts of 20; the rest are counted and summarised")
      .unit("1/s")
      .greater_than(0.0)
      .maximum(1000.0)
      .default_value(d.log_lines_per_s);
  return s;
}

ParameterSchema gate_settings_schema(const GateSettings& d) {
  ParameterSchema s;
  s.real("state_rate_hz", "device state publication rate; 0: every loop cycle")
      .unit("Hz")
      .minimum(0.0)
      .default_value(d.state_rate_hz);
  s.real("telemetry_rate_hz", "telemetry publication rate")
      .unit("Hz")
      .greater_than(0.0)
      .maximum(100.0)
      .default_value(d.telemetry_rate_hz);
  s.real("max_sample_age_s", "engine commands older than this by their source timestamp are rejected")
      .unit("s")
      .greater_than(0.0)
      .default_value(d.max_sample_age_s);
  s.real("max_force_n", "largest accepted engine force").unit("N").greater_than(0.0).default_value(d.max_force_n);
  s.real("max_torque_nm", "largest accepted engine torque")
      .unit("N m")
      .greater_than(0.0)
      .default_value(d.max_torque_nm);
  s.real("max_stiffness_n_per_m", "largest accepted local-model stiffness")
      .unit("N/m")
      .greater_than(0.0)
      .default_value(d.max_stiffness_n_per_m);
  s.real("max_rotational_stiffness_n_m_per_rad", "largest accepted local-model rotational stiffness")
      .unit("N m/rad")
      .greater_than(0.0)
      .default_value(d.max_rotational_stiffness_n_m_per_rad);
  s.real("max_damping_n_s_per_m", "largest accepted local-model damping")
      .unit("N s/m")
      .greater_than(0.0)
      .default_value(d.max_damping_n_s_per_m);
  s.real("max_rotational_damping_n_m_s", "largest accepted local-model rotational damping")
      .unit("N m s/rad")
      .greater_than(0.0)
      .default_value(d.max_rotational_damping_n_m_s);
  s.real("max_distance_m", "engine poses must lie within this distance of the device base")
      .unit("m")
      .greater_than(0.0)
      .default_value(d.max_distance_m);
  s.real("max_speed_m_s", "largest accepted engine twist, linear")
      .unit("m/s")
      .greater_than(0.0)
      .default_value(d.max_speed_m_s);
  s.real("max_angular_speed_rad_s", "largest accepted engine twist, angular")
      .unit("rad/s")
      .greater_than(0.0)
      .default_value(d.max_angular_speed_rad_s);
  s.boolean("lockstep_sync",
            "with the lockstep clock, each cycle waits for the owning engine's answer to the "
            "previous state (deterministic end-to-end runs)")
      .default_value(d.lockstep_sync);
  s.real("lockstep_wait_s",
         "longest wait (wall time) for an engine in lockstep before the loop stops waiting for "
         "it")
      .unit("s")
      .greater_than(0.0)
      .default_value(d.lockstep_wait_s);
  s.real("lockstep_start_wait_s",
         "with the lockstep clock, the first cycle waits up to this long (wall time) for "
         "engines to claim the devices and answer their states (lockstep_start_for); 0: no wait")
      .unit("s")
      .minimum(0.0)
      .maximum(600.0)
      .default_value(d.lockstep_start_wait_s);
  s.string("lockstep_start_for",
           "every: the first cycle waits for an engine on every device (runs with several engines are "
           "repeatable); any: for the first engine")
      .choices({"every", "any"})
      .default_value(std::string(d.lockstep_start_every ? "every" : "any"));
  s.string("tuning_by",
           "who may set a claimed device's tunable parameters (not safety.*): owner, or anyone (a console tuning "
           "while an engine runs; the owner is told of every set as a parameter event)")
      .choices({"owner", "anyone"})
      .default_value(std::string(d.tuning_by_anyone ? "anyone" : "owner"));
  s.real("claim_grace_s",
         "a claim whose peer shows no sign of life (no live engine command writer, no open connection) this "
         "long after the claim ends (a claimant that cannot be watched)")
      .unit("s")
      .greater_than(0.0)
      .maximum(1.0)
      .default_value(d.claim_grace_s);
  s.real("claim_hold_s",
         "a claimant that is still there but has shown no sign of life this long (frozen or killed: no live "
         "command writer) loses its claim; its forces fade at the command deadline meanwhile")
      .unit("s")
      .minimum(0.5)
      .maximum(60.0)
      .default_value(d.claim_hold_s);
  return s;
}

ParameterSchema server_settings_schema() {
  ParameterSchema s;
  s.real("rate_hz", "control loop rate").unit("Hz").minimum(100.0).maximum(20000.0).default_value(2000.0);
  s.string("clock",
           "realtime: absolute deadlines on the monotonic clock; lockstep: virtual clock, as fast as possible; device: "
           "one cycle per tick of a device whose SDK owns the servo loop (OpenHaptics' scheduler, a service's states)")
      .choices({"realtime", "lockstep", "device"})
      .default_value(std::string("realtime"));
  s.string("clock_device",
           "clock: device - the device whose ticks clock the session's loop; empty: the one device that can")
      .default_value(std::string());
  s.real("duration_s", "session length; 0 runs until SIGINT/SIGTERM").unit("s").minimum(0.0).default_value(0.0);
  s.integer("seed", "seed of every random process (simulated noise), per device derived from it")
      .minimum(0)
      .default_value(std::int64_t{1});
  s.integer("realtime_priority", "SCHED_FIFO priority of the loop thread; 0 keeps the normal scheduler")
      .minimum(0)
      .maximum(99)
      .default_value(std::int64_t{80});
  s.boolean("lock_memory", "lock all pages in memory (mlockall) in realtime mode").default_value(true);
  s.integer("cpu_dma_latency_us",
            "with a real-time loop (realtime clock, realtime_priority above 0), hold the kernel's CPU latency limit "
            "(/dev/cpu_dma_latency, as cyclictest does) at this many microseconds while the session runs: 0 keeps "
            "the CPUs out of idle states that take long to leave (docs/measurements.md: it halves the loop's "
            "wake-up latency on a virtual machine); -1 leaves it alone")
      .minimum(-1)
      .maximum(2000000)
      .default_value(std::int64_t{0});
  s.integer("cpu", "pin the loop thread to this CPU; -1 does not pin")
      .minimum(-1)
      .maximum(1023)
      .default_value(std::int64_t{-1});
  s.real("shutdown_ramp_s", "torques ramp linearly to zero over this time when the session ends")
      .unit("s")
      .minimum(0.0)
      .maximum(5.0)
      .default_value(0.2);
  return s;
}

namespace {
SessionConfig read_session_config(const std::string& text, const std::filesystem::path& path,
                                  const std::vector<std::string>& overrides, std::vector<AppliedOverride>& applied);
}  // namespace

SessionConfig load_session_config(const std::filesystem::path& path, const std::vector<std::string>& overrides) {
  const std::string file = path.string();
  if (!std::filesystem::exists(path)) throw ConfigError(file, 0, "", "no such file");
  std::string text;
  try {
    text = read_input_file(path, "session file");
  } catch (const std::runtime_error& e) {
    std::string message = e.what();  // "<file>: what is wrong"; the error names the file itself
    if (message.rfind(file + ": ", 0) == 0) message.erase(0, file.size() + 2);
    throw ConfigError(file, 0, "", message);
  }
  return parse_session_config(text, path, overrides);
}

SessionConfig parse_session_config(const std::string& text, const std::filesystem::path& path,
                                   const std::vector<std::string>& overrides) {
  // Every error names the file: a YAML conversion the readers did not anticipate becomes a located error too;
  // an error in an overridden value names the override.
  std::vector<AppliedOverride> applied;
  try {
    return read_session_config(text, path, overrides, applied);
  } catch (const YAML::Exception& e) {
    throw ConfigError(path.string(), e.mark.is_null() ? 0 : e.mark.line + 1, "", "YAML: " + e.msg);
  } catch (const ConfigError& e) {
    throw_if_overridden(e, applied);
    throw;
  }
}

namespace {
SessionConfig read_session_config(const std::string& text, const std::filesystem::path& path,
                                  const std::vector<std::string>& overrides, std::vector<AppliedOverride>& applied) {
  const std::string file = path.string();
  YAML::Node root = load_yaml_document(text, file);  // bounded, no duplicate keys, no shared nodes
  if (!root.IsDefined() || root.IsNull()) throw ConfigError(file, 0, "", "the file is empty");
  applied = apply_overrides(root, overrides);

  SessionConfig config;
  config.file = path;
  config.overrides = applied;
  MappingReader top(
      root, "", file,
      {"server", "dds", "gate", "live_view", "engine_socket", "teleoperation", "ros2", "scene", "devices", "groups"});
  config.server = read_server(top.optional("server"), file, path.parent_path());
  config.dds = read_dds(top.optional("dds"), file, path.parent_path());
  config.gate = read_gate(top.optional("gate"), top.optional("dds"), file);
  config.live_view = read_live_view(top.optional("live_view"), file);
  config.engine_socket = read_engine_socket(top.optional("engine_socket"), file, path.parent_path());
  config.scene = read_scene(top.optional("scene"), file);
  config.ros2 = read_ros2(top.optional("ros2"), file);
  if (config.ros2.enabled && config.ros2.rate_hz > config.server.rate_hz)
    throw ConfigError(file, root["ros2"]["rate_hz"].IsDefined() ? line_of(root["ros2"]["rate_hz"]) : config.ros2.line,
                      "ros2.rate_hz",
                      "more than the loop's rate (server.rate_hz: " + std::to_string(config.server.rate_hz) + " Hz)");

  const YAML::Node devices = top.required("devices");
  if (!devices.IsSequence() || devices.size() == 0)
    throw ConfigError(file, line_of(devices), "devices", "expected a non-empty list of devices");
  std::set<std::string> names;
  for (std::size_t i = 0; i < devices.size(); ++i) {
    const std::string key_path = "devices[" + std::to_string(i) + "]";
    std::vector<std::string> allowed;
    for (const EntryKey& k : device_entry_keys()) allowed.emplace_back(k.key);
    MappingReader reader(devices[i], key_path, file, allowed);
    DeviceConfig device;
    device.name = reader.required_string("name");
    if (!valid_device_name(device.name))
      throw ConfigError(file, line_of(devices[i]["name"]), reader.path_of("name"),
                        "device name '" + device.name + "' must be 1-31 characters of letters, digits, '_' and '-'");
    if (!names.insert(device.name).second)
      throw ConfigError(file, line_of(devices[i]["name"]), reader.path_of("name"),
                        "device name '" + device.name + "' is used twice");
    device.device = read_plugin(reader.required("device"), reader.path_of("device"), file);
    device.virtual_model = read_optional_plugin(reader, "virtual_model");
    device.inverse_kinematics = read_optional_plugin(reader, "inverse_kinematics");
    device.controller = read_plugin(reader.required("controller"), reader.path_of("controller"), file);
    if (reader.optional("scheme").IsDefined()) device.scheme = reader.required_string("scheme");
    read_schemes(reader, device);
    if (const YAML::Node n = reader.optional("engine_deadline_s"); n.IsDefined())
      device.engine_deadline_s = read_scalar_real(n, reader.path_of("engine_deadline_s"), file, 0.001, 10.0);
    if (const YAML::Node n = reader.optional("engine_fade_s"); n.IsDefined())
      device.engine_fade_s = read_scalar_real(n, reader.path_of("engine_fade_s"), file, 0.0, 10.0);
    if (const YAML::Node n = reader.optional("engine_ramp_in_s"); n.IsDefined())
      device.engine_ramp_in_s = read_scalar_real(n, reader.path_of("engine_ramp_in_s"), file, 0.0, 10.0);
    device.safety = read_safety(reader.optional("safety"), file, reader.path_of("safety"), config.warnings);
    device.base_pose = read_base_pose(reader.optional("base_pose"), file, reader.path_of("base_pose"));
    device.collision = read_collision(reader.optional("collision"), file, reader.path_of("collision"));
    config.devices.push_back(std::move(device));
  }
  for (std::size_t i = 0; i < config.ros2.commands.size(); ++i)
    if (std::none_of(config.devices.begin(), config.devices.end(),
                     [&](const DeviceConfig& d) { return d.name == config.ros2.commands[i]; }))
      throw ConfigError(file, config.ros2.command_lines[i], "ros2.commands",
                        "no device '" + config.ros2.commands[i] + "' in this session");
  config.groups = read_groups(top.optional("groups"), file, config.devices);
  config.teleoperation = read_teleoperation(top.optional("teleoperation"), file);
  if (TeleoperationSettings& t = config.teleoperation; t.enabled) {
    if (!config.dds.enabled)
      throw ConfigError(file, t.line, "teleoperation",
                        "the link travels over the DDS interface: add the dds section (both servers in one domain)");
    if (t.device.empty()) {
      if (config.devices.size() != 1)
        throw ConfigError(file, t.line, "teleoperation.device", "the session has several devices: name the linked one");
      t.device = config.devices.front().name;
    }
    if (std::none_of(config.devices.begin(), config.devices.end(),
                     [&](const DeviceConfig& d) { return d.name == t.device; }))
      throw ConfigError(file, line_of(root["teleoperation"]["device"]), "teleoperation.device",
                        "no device '" + t.device + "' in this session");
    if (!valid_device_name(t.peer))
      throw ConfigError(file, line_of(root["teleoperation"]["peer"]), "teleoperation.peer",
                        "device name '" + t.peer + "' must be 1-31 characters of letters, digits, '_' and '-'");
    if (t.peer == t.device)
      throw ConfigError(file, line_of(root["teleoperation"]["peer"]), "teleoperation.peer",
                        "the peer is the other server's device; '" + t.peer + "' is this one's");
    // A device has one holder for the session: the link or ROS 2, not both.
    for (std::size_t i = 0; i < config.ros2.commands.size(); ++i)
      if (config.ros2.commands[i] == t.device)
        throw ConfigError(file, config.ros2.command_lines[i], "ros2.commands",
                          "'" + t.device + "' is the teleoperation link's: ROS 2 cannot command it too");
  }
  return config;
}

}  // namespace

const char* clock_name(ClockMode mode) noexcept {
  switch (mode) {
    case ClockMode::lockstep:
      return "lockstep";
    case ClockMode::device:
      return "device";
    case ClockMode::realtime:
      break;
  }
  return "realtime";
}

ClockMode clock_mode(const std::string& name) {
  return name == "lockstep" ? ClockMode::lockstep : name == "device" ? ClockMode::device : ClockMode::realtime;
}

}  // namespace hapticd::server
