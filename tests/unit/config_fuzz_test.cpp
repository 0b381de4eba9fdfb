// Bounded randomised fuzzing of the session-file loader (fixed seed, a fixed number of inputs): mutations of
// the shipped session files - flipped and dropped characters, removed or duplicated lines, values replaced by
// hostile ones (NaN, huge, negative, wrong type, deep nesting). Whatever the input, loading and building either
// succeeds or throws a ConfigError naming the file; nothing else escapes and nothing crashes (run under the
// asan preset too).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "assembly/session_builder.hpp"
#include "config/config_error.hpp"
#include "config/session_config.hpp"
#include "loader/plugin_loader.hpp"
#include "support/temp_file.hpp"
#include "support/test_paths.hpp"

namespace hapticd::server {
namespace {

std::vector<std::string> seed_files() {
  std::vector<std::string> texts;
  for (const char* name : {"config/sessions/demo.yaml", "config/sessions/vishard3/admittance-wall.yaml",
                           "config/sessions/vishard3/impedance-friction-compensation.yaml",
                           "config/sessions/vishard3/scheme-switching.yaml"}) {
    std::ifstream in(hapticd::test::source_dir() + "/" + name);
    std::stringstream ss;
    ss << in.rdbuf();
    // Paths relative to the session's folder, made absolute (the mutants live in a temporary folder).
    std::string t = ss.str();
    for (const std::string rel : {"../../urdf/", "../urdf/", "../../friction/"}) {
      const std::string abs = hapticd::test::source_dir() + "/config/" + rel.substr(rel.rfind("../") + 3);
      for (std::size_t at = t.find(rel); at != std::string::npos; at = t.find(rel, at + abs.size()))
        t.replace(at, rel.size(), abs);
    }
    texts.push_back(t);
  }
  // A session with every safety key.
  texts.push_back(R"(server: {clock: lockstep, duration_s: 0.1}
devices:
  - name: axis
    device: {plugin: test_mass_spring, parameters: {encoder_resolution_m: 1.0e-6}}
    controller: {plugin: test_pd, parameters: {kp: 400, kd: 20}}
    safety: {thermal_time_constant_s: 30, joint_damping_from: 0.75, joint_fault_at: 0.95, max_speed_m_s: 1.5,
             workspace_min_m: [-0.1, -0.1, -0.1], workspace_max_m: [0.1, 0.1, 0.1], max_force_n: 80,
             soft_start_s: 0.2, passivity_control: true, safe_damping_s: 0.5, history_cycles: 50}
)");
  return texts;
}

const std::vector<std::string> kHostile = {".nan",
                                           "-.inf",
                                           "1e308",
                                           "-1",
                                           "0",
                                           "abc",
                                           "[]",
                                           "{}",
                                           "[1, 2, 3, 4, 5]",
                                           "~",
                                           "\"\"",
                                           "{a: {b: {c: {d: [[[[1]]]]}}}}",
                                           "true",
                                           "-9223372036854775809",
                                           "0x7fffffff",
                                           "'\\x00'",
                                           "&anchor x",
                                           "*nothing",
                                           "!!binary AAAA",
                                           "1:2:3"};

std::string mutate(const std::string& text, std::mt19937_64& rng) {
  std::string s = text;
  std::uniform_int_distribution<int> how(0, 5);
  const int rounds = 1 + static_cast<int>(rng() % 3);
  for (int r = 0; r < rounds && !s.empty(); ++r) {
    const std::size_t at = rng() % s.size();
    switch (how(rng)) {
      case 0:  // flip a character
        s[at] = static_cast<char>(32 + rng() % 95);
        break;
      case 1:  // drop a span
        s.erase(at, 1 + rng() % 8);
        break;
      case 2: {  // replace a value after a colon by a hostile one
        const std::size_t colon = s.find(": ", at);
        if (colon == std::string::npos) break;
        const std::size_t end = s.find_first_of(",}\n", colon + 2);
        s.replace(colon + 2, (end == std::string::npos ? s.size() : end) - colon - 2,
                  kHostile[rng() % kHostile.size()]);
        break;
      }
      case 3: {  // drop a line
        const std::size_t begin = s.rfind('\n', at);
        const std::size_t end = s.find('\n', at);
        if (begin != std::string::npos && end != std::string::npos) s.erase(begin, end - begin);
        break;
      }
      case 4: {  // duplicate a line (duplicate keys, doubled devices)
        const std::size_t begin = s.rfind('\n', at);
        const std::size_t end = s.find('\n', at);
        if (begin != std::string::npos && end != std::string::npos) s.insert(end, s.substr(begin, end - begin));
        break;
      }
      default:  // insert indentation or a tab
        s.insert(at, rng() % 2 == 0 ? "  " : "\t");
        break;
    }
  }
  return s;
}

TEST(ConfigFuzz, EveryMutatedSessionLoadsOrFailsWithALocatedConfigError) {
  const auto seeds = seed_files();
  for (const auto& s : seeds) ASSERT_FALSE(s.empty());
  std::mt19937_64 rng(20261123);
  PluginLoader loader(PluginLoader::search_paths_for({hapticd::test::plugin_dir()}));
  int loaded = 0, built = 0, rejected = 0;
  const auto file = test::write_temp_file("fuzz.yaml", "");
  for (int i = 0; i < 3000; ++i) {
    const std::string text = mutate(seeds[static_cast<std::size_t>(i) % seeds.size()], rng);
    {
      std::ofstream out(file);
      out << text;
    }
    try {
      SessionConfig config = load_session_config(file);
      ++loaded;
      // Building loads and configures plugins: every 7th input (it is slower).
      if (i % 7 == 0) {
        config.server.plugin_paths.push_back(hapticd::test::plugin_dir());
        PluginLoader session_loader(PluginLoader::search_paths_for(config.server.plugin_paths));
        std::vector<ConfigureFailure> failures;
        (void)build_sessions(config, session_loader, &failures);
        ++built;
      }
    } catch (const ConfigError& e) {
      ++rejected;
      ASSERT_EQ(e.file(), file.string()) << e.what() << "\n--- input ---\n" << text;
      ASSERT_GE(e.line(), 0);
      ASSERT_FALSE(e.message().empty());
    } catch (const std::exception& e) {
      FAIL() << "not a ConfigError: " << e.what() << "\n--- input ---\n" << text;
    }
  }
  std::printf("3000 mutated sessions: %d loaded (%d built), %d rejected with a located error\n", loaded, built,
              rejected);
  EXPECT_GT(rejected, 300);  // the mutations do reach the checks
  EXPECT_GT(loaded, 300);    // and do not only produce garbage
}

}  // namespace
}  // namespace hapticd::server
