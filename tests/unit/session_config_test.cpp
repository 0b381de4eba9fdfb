// Every class of bad session file gives a ConfigError naming the file, the line and the key.
#include "config/session_config.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <thread>

#include "assembly/session_builder.hpp"
#include "config/config_error.hpp"
#include "loader/plugin_loader.hpp"
#include "support/temp_file.hpp"
#include "support/test_paths.hpp"

namespace hapticd::server {
namespace {

const std::string kHeader = "server:\n  plugin_paths: [" + hapticd::test::plugin_dir() + "]\n";

const std::string kValidDevices = R"(devices:
  - name: axis
    device:
      plugin: test_mass_spring
    controller:
      plugin: test_pd
)";

// 1-based line of the first occurrence of marker in text.
int line_of_marker(const std::string& text, const std::string& marker) {
  const auto pos = text.find(marker);
  EXPECT_NE(pos, std::string::npos) << "marker not in text: " << marker;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(pos), '\n'));
}

// Loads and builds the session (plugins included), as hapticd --check-config does.
void load_and_build(const std::filesystem::path& file) {
  const SessionConfig config = load_session_config(file);
  PluginLoader loader(config.server.plugin_paths);
  (void)build_sessions(config, loader);
}

struct BadConfig {
  const char* name;
  std::string text;         // the whole file
  std::string key;          // expected key path
  std::string line_marker;  // the error's line is the line of this text
  std::string message;      // expected part of the message
};

void PrintTo(const BadConfig& c, std::ostream* os) { *os << c.name; }

class BadConfigTest : public ::testing::TestWithParam<BadConfig> {};

TEST_P(BadConfigTest, NamesFileLineAndKey) {
  const BadConfig& c = GetParam();
  const auto file = test::write_temp_file("session.yaml", c.text);
  try {
    load_and_build(file);
    FAIL() << "accepted a bad config: " << c.name;
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), file.string());
    EXPECT_EQ(e.key(), c.key) << e.what();
    EXPECT_EQ(e.line(), line_of_marker(c.text, c.line_marker)) << e.what();
    EXPECT_NE(e.message().find(c.message), std::string::npos) << "message: " << e.what();
    EXPECT_EQ(std::string(e.what()).rfind(file.string() + ":" + std::to_string(e.line()) + ": " + c.key + ": ", 0), 0u)
        << e.what();
  }
}

std::string with_controller_parameters(const std::string& params) {
  return kHeader + kValidDevices + "      parameters:\n" + params;
}

std::string with_device_parameters(const std::string& params) {
  return kHeader + "devices:\n  - name: axis\n    device:\n      plugin: test_mass_spring\n      parameters:\n" +
         params + "    controller:\n      plugin: test_pd\n";
}

INSTANTIATE_TEST_SUITE_P(
    SessionFile, BadConfigTest,
    ::testing::Values(
        // Unknown keys, at every level, with a suggestion.
        BadConfig{"unknown_top_level_key", kHeader + "devcies:\n  - name: a\n", "devcies",
                  "devcies:", "did you mean 'devices'"},
        BadConfig{"unknown_server_key", kHeader + "  rate_hx: 1000\n" + kValidDevices, "server.rate_hx", "rate_hx",
                  "did you mean 'rate_hz'"},
        BadConfig{"unknown_device_key", kHeader + kValidDevices + "    controler:\n      plugin: test_pd\n",
                  "devices[0].controler", "controler", "did you mean 'controller'"},
        BadConfig{"unknown_plugin_entry_key", kHeader + kValidDevices + "      parameter:\n        kp: 1\n",
                  "devices[0].controller.parameter", "parameter:", "did you mean 'parameters'"},
        BadConfig{"unknown_parameter", with_controller_parameters("        gian: 3\n"),
                  "devices[0].controller.parameters.gian", "gian", "valid keys: kp, kd"},
        // Missing keys.
        BadConfig{"missing_devices", kHeader, "devices", "server:", "missing required key 'devices'"},
        BadConfig{"missing_controller",
                  kHeader + "devices:\n  - name: axis\n    device:\n      plugin: test_mass_spring\n",
                  "devices[0].controller", "name: axis", "missing required key 'controller'"},
        BadConfig{"missing_plugin_name",
                  kHeader + "devices:\n  - name: axis\n    device:\n      library: x\n"
                            "    controller:\n      plugin: test_pd\n",
                  "devices[0].device.plugin", "library: x", "missing required key 'plugin'"},
        BadConfig{"missing_required_parameter",
                  kHeader + kValidDevices + "    virtual_model:\n      plugin: test_sine_setpoint\n",
                  "devices[0].virtual_model.parameters.amplitude_m", "plugin: test_sine_setpoint",
                  "missing required parameter 'amplitude_m'"},
        // Wrong types.
        BadConfig{"string_for_real", with_controller_parameters("        kp: fast\n"),
                  "devices[0].controller.parameters.kp", "kp: fast", "expected a real number, got 'fast'"},
        BadConfig{"bool_for_real", with_controller_parameters("        kd: true\n"),
                  "devices[0].controller.parameters.kd", "kd: true", "expected a real number"},
        BadConfig{"real_for_integer", with_device_parameters("        substeps: 2.5\n"),
                  "devices[0].device.parameters.substeps", "substeps", "expected an integer"},
        BadConfig{"list_for_real", kHeader + "  rate_hz: [1000]\n" + kValidDevices, "server.rate_hz", "rate_hz",
                  "expected a real number, got a list"},
        BadConfig{"devices_not_a_list", kHeader + "devices: 3\n", "devices", "devices: 3", "expected a non-empty list"},
        BadConfig{"device_not_a_mapping", kHeader + "devices:\n  - axis\n", "devices[0]", "- axis",
                  "expected a mapping"},
        // Out of range.
        BadConfig{"below_minimum", with_controller_parameters("        kp: -3\n"),
                  "devices[0].controller.parameters.kp", "kp: -3", "below the minimum 0"},
        BadConfig{"above_maximum", kHeader + "  rate_hz: 50000\n" + kValidDevices, "server.rate_hz", "rate_hz",
                  "above the maximum 20000"},
        BadConfig{"exclusive_minimum", with_device_parameters("        mass_kg: 0\n"),
                  "devices[0].device.parameters.mass_kg", "mass_kg", "must be greater than 0"},
        BadConfig{"not_a_choice", kHeader + "  clock: fast\n" + kValidDevices, "server.clock", "clock: fast",
                  "not one of: realtime, lockstep"},
        BadConfig{"rejected_by_configure", with_device_parameters("        stiffness_n_per_m: 1.0e9\n"),
                  "devices[0].device.parameters.stiffness_n_per_m", "stiffness_n_per_m", "natural frequency"},
        // Devices.
        BadConfig{"duplicate_device_name",
                  kHeader + kValidDevices +
                      "  - name: axis\n    device: {plugin: test_mass_spring}\n"
                      "    controller: {plugin: test_pd}\n",
                  "devices[1].name", "  - name: axis\n    device: {", "used twice"},
        BadConfig{"invalid_device_name",
                  kHeader + "devices:\n  - name: my arm\n    device: {plugin: test_mass_spring}\n"
                            "    controller: {plugin: test_pd}\n",
                  "devices[0].name", "my arm", "must be 1-31 characters"},
        BadConfig{"empty_device_list", kHeader + "devices: []\n", "devices", "devices: []", "non-empty list"},
        // The live view.
        BadConfig{"live_view_port", kHeader + kValidDevices + "live_view:\n  port: 70000\n", "live_view.port",
                  "port: 70000", "above the maximum 65535"},
        BadConfig{"live_view_address", kHeader + kValidDevices + "live_view:\n  address: localhost\n",
                  "live_view.address", "address: localhost", "not an IP address"},
        BadConfig{"live_view_unknown_key", kHeader + kValidDevices + "live_view:\n  prot: 1\n", "live_view.prot",
                  "prot: 1", "unknown key"},
        // ROS 2's topics.
        BadConfig{"ros2_namespace", kHeader + kValidDevices + "ros2:\n  namespace: hapticd\n", "ros2.namespace",
                  "namespace: hapticd", "is not a ROS 2 namespace"},
        BadConfig{"ros2_world_frame", kHeader + kValidDevices + "ros2:\n  world_frame: /world\n", "ros2.world_frame",
                  "world_frame: /world", "is not a frame id"},
        BadConfig{"ros2_rate_above_the_loop", kHeader + "  rate_hz: 500\n" + kValidDevices + "ros2:\n  rate_hz: 1000\n",
                  "ros2.rate_hz", "rate_hz: 1000", "more than the loop's rate"},
        BadConfig{"ros2_commands_unknown_device", kHeader + kValidDevices + "ros2:\n  commands: [axis, arm]\n",
                  "ros2.commands", "commands: [axis, arm]", "no device 'arm' in this session"},
        BadConfig{"ros2_commands_the_teleoperation_device",
                  kHeader + kValidDevices +
                      "dds: {domain_id: 3}\nteleoperation: {peer: far, role: master}\nros2:\n  commands: [axis]\n",
                  "ros2.commands", "commands: [axis]", "is the teleoperation link's"},
        BadConfig{"ros2_unknown_key", kHeader + kValidDevices + "ros2:\n  domian_id: 3\n", "ros2.domian_id",
                  "domian_id: 3", "unknown key"},
        // The gate's settings: in the gate section, or (older sessions) in dds - not both.
        BadConfig{"gate_key_in_dds_and_gate",
                  kHeader + kValidDevices + "dds:\n  max_force_n: 100\ngate:\n  max_force_n: 50\n", "dds.max_force_n",
                  "max_force_n: 100", "also given in the gate section (gate.max_force_n)"},
        BadConfig{"gate_unknown_key", kHeader + kValidDevices + "gate:\n  max_froce_n: 1\n", "gate.max_froce_n",
                  "max_froce_n: 1", "unknown key"},
        // Duplicate keys (hardening round 3, item 10): the second wins or the first, by the reader's whim.
        BadConfig{"duplicate_server_key", kHeader + "  rate_hz: 2000\n  rate_hz: 500\n" + kValidDevices,
                  "server.rate_hz", "rate_hz: 500", "given twice in one mapping (lines 3 and 4)"},
        BadConfig{"duplicate_safety_key",
                  kHeader + kValidDevices + "    safety: {max_stall_s: 0.02, max_stall_s: 0.5}\n",
                  "devices[0].safety.max_stall_s", "safety:", "given twice"},
        BadConfig{"duplicate_device_entry_key", kHeader + kValidDevices + "    controller: {plugin: test_pd}\n",
                  "devices[0].controller", "controller: {plugin", "given twice"},
        // A safety function is turned off by saying so, and safety settings have physical bounds.
        BadConfig{"watchdog_zero", kHeader + kValidDevices + "    safety: {max_stall_s: 0}\n",
                  "devices[0].safety.max_stall_s", "safety:", "write 'off' to turn it off"},
        BadConfig{"overruns_zero", kHeader + kValidDevices + "    safety: {max_consecutive_overruns: 0}\n",
                  "devices[0].safety.max_consecutive_overruns", "safety:", "write 'off'"},
        BadConfig{"absurd_force_limit", kHeader + kValidDevices + "    safety: {max_force_n: 1e308}\n",
                  "devices[0].safety.max_force_n", "safety:", "above the maximum 2000"},
        // Plugins.
        BadConfig{"unknown_plugin",
                  kHeader + "devices:\n  - name: axis\n    device:\n      plugin: test_mass_spring\n"
                            "    controller:\n      plugin: test_pdd\n",
                  "devices[0].controller.plugin", "plugin: test_pdd", "no controller plugin named 'test_pdd'"},
        BadConfig{"wrong_plugin_kind",
                  kHeader + "devices:\n  - name: axis\n    device:\n      plugin: test_mass_spring\n"
                            "    controller: {plugin: test_mass_spring}\n",
                  "devices[0].controller.plugin", "{plugin: test_mass_spring}",
                  "is a device plugin, but a controller plugin is needed"},
        BadConfig{"missing_library",
                  kHeader + "devices:\n  - name: axis\n    device:\n      plugin: test_mass_spring\n"
                            "      library: no_such_library\n    controller:\n      plugin: test_pd\n",
                  "devices[0].device.plugin", "plugin: test_mass_spring",
                  "plugin library 'no_such_library' not found"}),
    [](const ::testing::TestParamInfo<BadConfig>& param_info) { return std::string(param_info.param.name); });

TEST(SessionConfig, YamlSyntaxErrorNamesTheLine) {
  const std::string text = kHeader + "devices:\n  - name: axis\n    device: {plugin: test_mass_spring\n";
  const auto file = test::write_temp_file("session.yaml", text);
  try {
    (void)load_session_config(file);
    FAIL() << "accepted broken YAML";
  } catch (const ConfigError& e) {
    EXPECT_GE(e.line(), 5);
    EXPECT_NE(e.message().find("YAML syntax error"), std::string::npos) << e.what();
  }
}

TEST(SessionConfig, MissingAndEmptyFiles) {
  EXPECT_THROW((void)load_session_config("/nonexistent/session.yaml"), ConfigError);
  const auto empty = test::write_temp_file("empty.yaml", "");
  try {
    (void)load_session_config(empty);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(e.message().find("empty"), std::string::npos);
  }
}

TEST(SessionConfig, ValidFileGivesDefaultsAndOverrides) {
  const auto file =
      test::write_temp_file("session.yaml", kHeader + "  rate_hz: 4000\n  clock: lockstep\n" + kValidDevices);
  const SessionConfig c = load_session_config(file);
  EXPECT_EQ(c.server.rate_hz, 4000.0);
  EXPECT_EQ(c.server.clock, ClockMode::lockstep);
  EXPECT_EQ(c.server.shutdown_ramp_s, 0.2);   // default
  EXPECT_EQ(c.server.cpu_dma_latency_us, 0);  // default: a real-time loop holds the CPUs out of deep idle
  ASSERT_EQ(c.devices.size(), 1u);
  EXPECT_EQ(c.devices[0].name, "axis");
  EXPECT_EQ(c.devices[0].controller.plugin, "test_pd");
  EXPECT_FALSE(c.devices[0].virtual_model.has_value());
  EXPECT_NO_THROW(load_and_build(file));
}

TEST(SessionConfig, LiveViewIsOffUnlessASectionTurnsItOn) {
  EXPECT_FALSE(load_session_config(test::write_temp_file("session.yaml", kHeader + kValidDevices)).live_view.enabled);
  // `live_view:` alone: on, loopback, the defaults.
  const SessionConfig on =
      load_session_config(test::write_temp_file("session.yaml", kHeader + kValidDevices + "live_view:\n"));
  EXPECT_TRUE(on.live_view.enabled);
  EXPECT_EQ(on.live_view.address, "127.0.0.1");
  EXPECT_EQ(on.live_view.port, 8765);
  EXPECT_EQ(on.live_view.rate_hz, 30.0);
  // An override makes the section (hapticd --live-view PORT is one).
  const SessionConfig set = load_session_config(test::write_temp_file("session.yaml", kHeader + kValidDevices),
                                                {"live_view.port=0", "live_view.address=::1"});
  EXPECT_TRUE(set.live_view.enabled);
  EXPECT_EQ(set.live_view.port, 0);
  EXPECT_EQ(set.live_view.address, "::1");
}

TEST(SessionConfig, TheGatesSettingsComeFromTheGateSectionOrFromDds) {
  // Issue 63: an engine socket without DDS is a session of its own (before: "the engine socket needs the dds
  // section"); its bounds are the gate section's.
  const SessionConfig socket_only = load_session_config(test::write_temp_file(
      "session.yaml",
      kHeader + kValidDevices + "engine_socket: {port: 0}\ngate: {max_force_n: 40, claim_hold_s: 2}\n"));
  EXPECT_TRUE(socket_only.engine_socket.enabled);
  EXPECT_FALSE(socket_only.dds.enabled);
  EXPECT_EQ(socket_only.gate.max_force_n, 40.0);
  EXPECT_EQ(socket_only.gate.claim_hold_s, 2.0);
  EXPECT_EQ(socket_only.gate.max_torque_nm, GateSettings{}.max_torque_nm);
  // A session written before the gate had a section: the same keys in dds.
  const SessionConfig older = load_session_config(
      test::write_temp_file("session.yaml", kHeader + kValidDevices + "dds: {domain_id: 3, max_force_n: 50}\n"));
  EXPECT_TRUE(older.dds.enabled);
  EXPECT_EQ(older.dds.domain_id, 3);
  EXPECT_EQ(older.gate.max_force_n, 50.0);
  EXPECT_FALSE(older.gate.tuning_by_anyone);
  // The gate section over the dds section's gate keys: an override that makes a gate section keeps what dds says.
  const SessionConfig set =
      load_session_config(test::write_temp_file("session.yaml", kHeader + kValidDevices + "dds: {max_force_n: 50}\n"),
                          {"gate.max_speed_m_s=1.5", "gate.tuning_by=anyone"});
  EXPECT_EQ(set.gate.max_speed_m_s, 1.5);
  EXPECT_EQ(set.gate.max_force_n, 50.0);
  EXPECT_TRUE(set.gate.tuning_by_anyone);
}

TEST(SessionConfig, ShippedConfigsAreValid) {
  for (const auto& entry : std::filesystem::directory_iterator(hapticd::test::source_dir() + "/config/sessions")) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    SessionConfig config = load_session_config(entry.path());
    config.server.plugin_paths.push_back(hapticd::test::plugin_dir());
    PluginLoader loader(config.server.plugin_paths);
    EXPECT_NO_THROW((void)build_sessions(config, loader));
  }
}

}  // namespace
}  // namespace hapticd::server

namespace hapticd::server {
namespace {

TEST(SessionConfig, AWatchdogTurnedOffIsSaidAndWarned) {
  const SessionConfig c = parse_session_config(
      kHeader + kValidDevices + "    safety: {max_stall_s: off, max_consecutive_overruns: off}\n", "off.yaml");
  EXPECT_EQ(c.devices[0].safety.max_stall_s, 0.0);
  EXPECT_EQ(c.devices[0].safety.max_consecutive_overruns, 0u);
  ASSERT_EQ(c.warnings.size(), 2u);
  EXPECT_NE(c.warnings[0].find("devices[0].safety.max_consecutive_overruns is off"), std::string::npos)
      << c.warnings[0];
  EXPECT_NE(c.warnings[1].find("devices[0].safety.max_stall_s is off"), std::string::npos) << c.warnings[1];
  EXPECT_TRUE(parse_session_config(kHeader + kValidDevices, "on.yaml").warnings.empty());
}

TEST(SessionConfig, AnOverrideThroughAnAliasChangesOnlyThePathItNames) {
  // The shipped dual-arm sessions share one chain through an anchor: `--set` on one arm changed the other too.
  const std::string text = kHeader + R"(devices:
  - name: left
    device: {plugin: test_mass_spring}
    controller: &pd
      plugin: test_pd
      parameters: {kp: 100, kd: 5}
  - name: right
    device: {plugin: test_mass_spring}
    controller: *pd
)";
  const SessionConfig c = parse_session_config(text, "alias.yaml", {"devices.left.controller.parameters.kp=300"});
  EXPECT_EQ(c.devices[0].controller.parameters["kp"].as<double>(), 300.0);
  EXPECT_EQ(c.devices[1].controller.parameters["kp"].as<double>(), 100.0);
  // The copy keeps its lines: an error inside the aliased chain still names one (the anchor's).
  EXPECT_EQ(c.devices[1].controller.line, 6);
  EXPECT_EQ(c.devices[1].controller.parameters.Mark().line + 1, 8);
}

TEST(SessionConfig, ADocumentWithTooManyValuesIsRefusedBeforeItIsBuilt) {
  std::string bomb = "a0: &a0 [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]\n";
  for (int i = 1; i < 9; ++i) {
    const std::string p = "*a" + std::to_string(i - 1);
    bomb += "a" + std::to_string(i) + ": &a" + std::to_string(i) + " [" + p;
    for (int k = 1; k < 10; ++k) bomb += ", " + p;
    bomb += "]\n";
  }
  try {
    (void)parse_session_config(bomb + "devices: [*a8]\n", "bomb.yaml");
    FAIL() << "an alias bomb was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("more than 100000 values"), std::string::npos) << e.what();
  }
}

TEST(SessionConfig, ADocumentThatContainsItselfIsRefusedBeforeItIsBuilt) {
  // What the session loader's fuzzer found: an alias inside the value its anchor names. yaml-cpp builds the
  // document as a cycle, and the duplicate-key check recursed until the stack overflowed.
  const std::string cycle =
      "devices:\n  - name: left\n    device: {plugin: sim}\n    virtual_model: &admittance\n      plugin: "
      "admittance\n      inner: *admittance\n";
  try {
    (void)parse_session_config(cycle, "cycle.yaml");
    FAIL() << "a document that contains itself was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("cycle.yaml:6"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("would contain itself"), std::string::npos) << e.what();
  }
  // Nesting deep enough to exhaust a walker's stack is refused too, with its line.
  std::string deep = "devices: ";
  for (int i = 0; i < 5000; ++i) deep += "[";
  try {
    (void)parse_session_config(deep + "\n", "deep.yaml");
    FAIL() << "5000 nested lists were accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("more than 64 deep"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hapticd::server

namespace hapticd::server {
namespace {

// Hardening round 4, item 8: the engine socket's token file or PEM file as a named pipe hung the server's start
// (std::ifstream waits for a writer), and as a device it would be read without end: each is a config error naming
// the key, at once.
TEST(SessionConfig, ATokenOrPemFileThatIsNoRegularFileIsAConfigErrorAtOnce) {
  const std::string fifo = ::testing::TempDir() + "session_config_token_fifo";
  (void)std::remove(fifo.c_str());
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto refused = [&](const std::string& key, const std::string& path) {
    const std::string text = kHeader + "dds: {domain_id: 7}\nengine_socket: {" + key + ": " + path +
                             (key == "token_file" ? "" : ", tls_private_key_file: " + path) + "}\n" + kValidDevices;
    const auto file = test::write_temp_file("session.yaml", text);
    auto done = std::make_shared<std::atomic<int>>(0);
    auto message = std::make_shared<std::string>();
    std::thread([file, key, done, message] {
      try {
        (void)load_session_config(file);
        done->store(1);
      } catch (const ConfigError& e) {
        *message = e.what();
        done->store(e.key() == "engine_socket." + key ? 2 : 3);
      }
    }).detach();
    for (int i = 0; i < 1000 && done->load() == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (done->load() == 0) {
      std::fprintf(stderr, "FAILED: reading engine_socket.%s = %s hangs\n", key.c_str(), path.c_str());
      std::_Exit(1);  // a hung thread cannot be joined
    }
    EXPECT_EQ(done->load(), 2) << *message;
    EXPECT_NE(message->find("not a regular file"), std::string::npos) << *message;
  };
  refused("token_file", fifo);
  refused("token_file", "/dev/zero");
  refused("tls_certificate_file", fifo);
  refused("tls_certificate_file", "/dev/zero");
  (void)std::remove(fifo.c_str());
}

}  // namespace
}  // namespace hapticd::server
