// Each plugin-loading failure has its own clear message; libraries outlive their objects.
#include "loader/plugin_loader.hpp"

#include <gtest/gtest.h>
#include <link.h>

#include <cstdlib>
#include <fstream>
#include <set>

#include "loader/elf_exports.hpp"
#include "support/test_paths.hpp"

namespace hapticd::server {
namespace {

std::string load_error(PluginLoader& loader, const std::string& library) {
  try {
    (void)loader.load_library(library);
  } catch (const PluginLoadError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(PluginLoader, FindsEveryKindInTheTestLibrary) {
  PluginLoader loader({hapticd::test::plugin_dir()});
  EXPECT_EQ(loader.find(PluginKind::device, "test_mass_spring", std::nullopt).descriptor->kind, PluginKind::device);
  EXPECT_EQ(loader.find(PluginKind::controller, "test_pd", std::nullopt).descriptor->kind, PluginKind::controller);
  EXPECT_EQ(loader.find(PluginKind::virtual_model, "test_sine_setpoint", "hapticd_test_plugins").descriptor->kind,
            PluginKind::virtual_model);
  EXPECT_EQ(loader.find(PluginKind::inverse_kinematics, "test_axis_ik", std::nullopt).descriptor->kind,
            PluginKind::inverse_kinematics);
}

TEST(PluginLoader, MissingFile) {
  PluginLoader loader({hapticd::test::plugin_dir()});
  EXPECT_NE(load_error(loader, "no_such_plugins")
                .find("plugin library 'no_such_plugins' not found (looked for "
                      "libno_such_plugins.so in: " +
                      hapticd::test::plugin_dir()),
            std::string::npos);
  EXPECT_NE(load_error(loader, "/nowhere/libx.so").find("does not exist"), std::string::npos);
}

TEST(PluginLoader, NotALoadableLibrary) {
  PluginLoader loader({});
  // A text file with a .so name.
  const std::string path = ::testing::TempDir() + "/libgarbage.so";
  FILE* f = std::fopen(path.c_str(), "w");
  std::fputs("not an ELF file", f);
  std::fclose(f);
  const std::string e = load_error(loader, path);
  EXPECT_NE(e.find("is not a hapticd plugin library"), std::string::npos) << e;
  EXPECT_NE(e.find("it was not loaded"), std::string::npos) << e;
}

TEST(PluginLoader, MissingSymbol) {
  PluginLoader loader({hapticd::test::fixture_dir()});
  const std::string e = load_error(loader, "hapticd_fixture_not_a_plugin");
  EXPECT_NE(e.find("is not a hapticd plugin library: it exports no 'hapticd_plugin_api_version' symbol"),
            std::string::npos)
      << e;
}

TEST(PluginLoader, WrongApiVersion) {
  PluginLoader loader({hapticd::test::fixture_dir()});
  const std::string e = load_error(loader, "hapticd_fixture_wrong_api");
  EXPECT_NE(e.find("was built against plugin API version " + std::to_string(kApiVersion + 1) +
                   ", this server uses version " + std::to_string(kApiVersion)),
            std::string::npos)
      << e;
}

TEST(PluginLoader, WrongKind) {
  PluginLoader loader({hapticd::test::plugin_dir()});
  try {
    (void)loader.find(PluginKind::controller, "test_mass_spring", std::nullopt);
    FAIL();
  } catch (const PluginLoadError& e) {
    EXPECT_NE(std::string(e.what()).find("is a device plugin, but a controller plugin is needed"), std::string::npos)
        << e.what();
  }
}

TEST(PluginLoader, UnknownNameListsTheAvailableOnes) {
  PluginLoader loader({hapticd::test::plugin_dir()});
  try {
    (void)loader.find(PluginKind::controller, "no_such_controller", std::nullopt);
    FAIL();
  } catch (const PluginLoadError& e) {
    EXPECT_NE(std::string(e.what()).find("no controller plugin named 'no_such_controller'"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("available: "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("test_pd"), std::string::npos) << e.what();
  }
}

TEST(PluginLoader, ScanningReportsBrokenLibrariesButKeepsGoing) {
  PluginLoader loader({hapticd::test::fixture_dir(), hapticd::test::plugin_dir()});
  std::vector<std::string> problems;
  const auto all = loader.list_all(&problems);
  std::set<std::string> names;
  for (const auto& handle : all) names.insert(handle.descriptor->name);
  // Every in-tree plugin library was read past the two broken fixtures.
  for (const char* expected :
       {"test_mass_spring", "test_pd", "test_sine_setpoint", "test_axis_ik", "sim", "admittance", "impedance",
        "friction_identification", "inverse_jacobian", "transposed_jacobian", "computed_torque", "joint_pd",
        "newton_ik", "redundancy_ik", "vishard10_ik", "resolved_acceleration"}) {
    EXPECT_EQ(names.count(expected), 1u) << expected;
  }
  // The library of another API version is reported; the one that is no plugin at all is passed over unloaded
  // (its initialiser would leave a mark).
  EXPECT_EQ(problems.size(), 1u);
  EXPECT_EQ(std::getenv("HAPTICD_FIXTURE_NOT_A_PLUGIN_LOADED"), nullptr);
}

TEST(PluginLoader, ASystemLibraryFolderIsNotLoaded) {
  // The attack: plugin_paths: [/usr/lib/x86_64-linux-gnu] dlopened all 168 system libraries. Now none is
  // loaded: a library is opened only when its symbol table exports hapticd's entry point.
  std::size_t before = 0;
  dl_iterate_phdr([](dl_phdr_info*, std::size_t, void* n) { return ++*static_cast<std::size_t*>(n), 0; }, &before);
  PluginLoader loader({"/usr/lib/x86_64-linux-gnu", "/lib/x86_64-linux-gnu"});
  std::vector<std::string> problems;
  EXPECT_TRUE(loader.list_all(&problems).empty());
  EXPECT_TRUE(problems.empty());
  std::size_t after = 0;
  dl_iterate_phdr([](dl_phdr_info*, std::size_t, void* n) { return ++*static_cast<std::size_t*>(n), 0; }, &after);
  EXPECT_EQ(after, before) << "libraries were loaded while scanning a system folder";
}

TEST(PluginLoader, TheElfCheckFindsTheEntryPoint) {
  EXPECT_TRUE(
      elf_exports_symbol(hapticd::test::plugin_dir() + "/libhapticd_test_plugins.so", "hapticd_plugin_api_version"));
  EXPECT_FALSE(elf_exports_symbol(hapticd::test::fixture_dir() + "/libhapticd_fixture_not_a_plugin.so",
                                  "hapticd_plugin_api_version"));
  EXPECT_TRUE(elf_exports_symbol(hapticd::test::fixture_dir() + "/libhapticd_fixture_not_a_plugin.so",
                                 "some_unrelated_function"));
  EXPECT_FALSE(elf_exports_symbol("/dev/zero", "x"));
  EXPECT_FALSE(elf_exports_symbol("/nonexistent.so", "x"));
  // Truncated and corrupted copies of a real library: never a crash, never a false yes.
  std::ifstream in(hapticd::test::plugin_dir() + "/libhapticd_test_plugins.so", std::ios::binary);
  const std::string image((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string path = ::testing::TempDir() + "/libcut.so";
  std::uint64_t state = 1;
  for (int k = 0; k < 200; ++k) {
    std::string copy = image.substr(0, k < 100 ? image.size() * static_cast<std::size_t>(k) / 100 : image.size());
    for (int flips = 0; k >= 100 && flips < 64; ++flips) {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      copy[(state >> 33) % std::min<std::size_t>(copy.size(), 4096)] ^= static_cast<char>(state >> 20);
    }
    std::ofstream(path, std::ios::binary) << copy;
    (void)elf_exports_symbol(path, "hapticd_plugin_api_version");
  }
}

TEST(PluginLoader, EnvironmentPathIsSearched) {
  ::setenv("HAPTICD_PLUGIN_PATH", "/a:/b", 1);
  const auto paths = PluginLoader::search_paths_for({"/configured"});
  ::unsetenv("HAPTICD_PLUGIN_PATH");
  ASSERT_GE(paths.size(), 4u);
  EXPECT_EQ(paths[0], "/configured");
  EXPECT_EQ(paths[1], "/a");
  EXPECT_EQ(paths[2], "/b");
  EXPECT_EQ(paths[3].filename(), "plugins");
}

TEST(PluginLoader, ObjectsKeepTheirLibraryLoaded) {
  PluginInstance<Controller> controller;
  {
    PluginLoader loader({hapticd::test::plugin_dir()});
    controller = create_plugin<Controller>(loader.find(PluginKind::controller, "test_pd", std::nullopt));
  }  // the loader is gone; the instance still holds the library
  ASSERT_TRUE(controller.library->library.is_loaded());
  EXPECT_EQ(controller.library.use_count(), 1);
  DeviceDescription d;
  d.joints.resize(1);
  PluginContext context;
  context.device = &d;
  Parameters p;
  const ParameterSchema schema = controller.descriptor->parameter_schema();
  for (const auto& spec : schema.specs()) p.set(spec.name, *spec.default_value);
  EXPECT_NO_THROW(controller->configure(p, context));  // its code is still mapped
}

}  // namespace
}  // namespace hapticd::server
