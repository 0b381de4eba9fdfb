// Overrides of a session file (server/src/config/config_overrides): "path=value" set before validation, a device
// entry by its name or index, errors that name the override.
#include "config/config_overrides.hpp"

#include <gtest/gtest.h>

#include "config/config_error.hpp"

namespace hapticd::server {
namespace {

YAML::Node session() {
  return YAML::Load("server: {seed: 1}\ndevices:\n  - name: left\n    controller: {plugin: pd}\n  - name: right\n");
}

TEST(ConfigOverrides, SetsScalarsListsAndNewKeysInOrder) {
  YAML::Node root = session();
  const auto applied = apply_overrides(root, {"server.seed=7", "devices.right.controller.parameters.kp=[1, 2]",
                                              "devices.0.controller.plugin=pid", "server.seed=8"});
  EXPECT_EQ(root["server"]["seed"].as<int>(), 8);  // the last one wins
  EXPECT_EQ(root["devices"][1]["controller"]["parameters"]["kp"].as<std::vector<int>>(), (std::vector<int>{1, 2}));
  EXPECT_EQ(root["devices"][0]["controller"]["plugin"].as<std::string>(), "pid");
  EXPECT_EQ(root["devices"][0]["name"].as<std::string>(), "left");  // the rest of the entry kept
  ASSERT_EQ(applied.size(), 4u);
  EXPECT_EQ(applied[1].key_path, "devices[1].controller.parameters.kp");
  EXPECT_EQ(applied[2].key_path, "devices[0].controller.plugin");
}

TEST(ConfigOverrides, MalformedOverridesAreErrorsThatNameThem) {
  const auto error_of = [](const std::string& text) {
    YAML::Node root = session();
    try {
      apply_overrides(root, {text});
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error_of("server.seed").find("override 'server.seed'"), std::string::npos);
  EXPECT_NE(error_of("=3").find("expected <key.path>=<value>"), std::string::npos);
  EXPECT_NE(error_of("devices.middle.controller=1").find("no entry named 'middle'"), std::string::npos);
  EXPECT_NE(error_of("devices.5.controller=1").find("no entry named '5'"), std::string::npos);
  EXPECT_NE(error_of("server.seed.x=1").find("is not a mapping"), std::string::npos);
  EXPECT_NE(error_of("server..seed=1").find("an empty key"), std::string::npos);
  EXPECT_NE(error_of("server.seed=[1, 2").find("not YAML"), std::string::npos);
}

TEST(ConfigOverrides, AnErrorInAnOverriddenValueNamesTheOverride) {
  const std::vector<AppliedOverride> applied{
      {"devices.left.controller.parameters.kp=-1", "devices[0].controller.parameters.kp"}};
  const ConfigError inside("s.yaml", 1, "devices[0].controller.parameters.kp", "must be positive");
  try {
    throw_if_overridden(inside, applied);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), "override 'devices.left.controller.parameters.kp=-1'");
    EXPECT_EQ(e.key(), "devices[0].controller.parameters.kp");
    EXPECT_EQ(e.message(), "must be positive");
  }
  // Elsewhere in the file: the file's error stands.
  EXPECT_NO_THROW(throw_if_overridden(ConfigError("s.yaml", 9, "devices[0].controller.parameters.kd", "bad"), applied));
  EXPECT_NO_THROW(
      throw_if_overridden(ConfigError("s.yaml", 9, "devices[0].controller.parameters.kpx", "bad"), applied));
}

}  // namespace
}  // namespace hapticd::server
