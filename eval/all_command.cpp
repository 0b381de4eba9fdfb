#include "all_command.hpp"

#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "eval_options.hpp"

namespace hapticd::eval {
namespace {

// The experiments of the chapter in the order the report shows them; every_device: its protocol is written for
// ViSHaRD6 and ViSHaRD10 too (the others are for ViSHaRD3's translational handle).
struct Experiment {
  std::string name;
  bool every_device;
};
const std::vector<Experiment> kExperiments{
    {"output-capability", true}, {"backdrivability", false}, {"force-response", false}, {"minimum-inertia", true},
    {"force-gain", false},       {"tracking", false},        {"z-width", false},        {"transparency", false},
    {"friction", true},          {"teleoperation", false}};

// Runs this program with the arguments (a child process per experiment: each has its own options and a fault
// in one does not stop the others). Returns its exit status.
int run_self(const std::vector<std::string>& arguments) {
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>(self.c_str()));
  for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  std::fflush(stdout);  // what this process printed comes before the child's output
  const pid_t pid = fork();
  if (pid < 0) return 127;
  if (pid == 0) {
    execv(self.c_str(), argv.data());
    _exit(127);
  }
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) return 127;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

int run(const CommonOptions& o) {
  std::vector<std::string> common{"--device",    o.device, "--out", o.out, "--seed", std::to_string(o.seed),
                                  "--no-figures"};
  if (o.quick) common.push_back("--quick");
  if (o.no_friction_compensation) common.push_back("--no-friction-compensation");
  for (const std::string& line : o.sim_parameters) {  // back from "key: value" to KEY=VALUE
    const auto colon = line.find(": ");
    common.push_back("--sim");
    common.push_back(line.substr(0, colon) + "=" + line.substr(colon + 2));
  }
  std::filesystem::create_directories(o.out);
  int failed = 0;
  for (const auto& [experiment, every_device] : kExperiments) {
    if (!every_device && o.device != "vishard3") continue;
    std::vector<std::string> arguments{experiment};
    if (experiment == "output-capability") {
      arguments.insert(arguments.end(), {"--device", o.device, "--json",
                                         (std::filesystem::path(o.out) / "output-capability-table.json").string()});
      if (o.quick) arguments.insert(arguments.end(), {"--points", "3"});
    } else {
      arguments.insert(arguments.end(), common.begin(), common.end());
    }
    fmt::print("== hapticd-eval {}\n", experiment);
    const auto start = std::chrono::steady_clock::now();
    const int status = run_self(arguments);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    fmt::print("== {} {} in {:.1f} s\n\n", experiment, status == 0 ? "done" : fmt::format("FAILED ({})", status),
               seconds);
    if (status != 0) ++failed;
  }
  if (!o.no_figures) render_report(o.report());
  if (failed > 0) {
    std::cerr << "hapticd-eval all: " << failed << " experiment(s) failed\n";
    return 1;
  }
  return 0;
}

}  // namespace

void add_all_command(CLI::App& app, int& exit_code) {
  auto o = command_options<CommonOptions>();
  CLI::App* cmd = app.add_subcommand(
      "all",
      "Every experiment of the chapter the device has a protocol for in turn (vishard6, vishard10: output "
      "capability, minimum inertia, friction), then one report");
  add_common_options(cmd, *o, {"vishard3", "vishard6", "vishard10"});
  cmd->callback([o, &exit_code] { exit_code = run(*o); });
}

}  // namespace hapticd::eval
