#pragma once
// The options every experiment subcommand takes: the device, where the results go, quick (CI-sized) runs.
#include <CLI/CLI.hpp>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "report/report.hpp"

namespace hapticd::eval {

struct CommonOptions {
  std::string device = "vishard3";
  std::string out = "eval-results";
  bool quick = false;       // a short run of the same protocol (CI): fewer points, shorter windows
  bool no_figures = false;  // JSON only
  std::uint64_t seed = 1;
  // The simulator's parameters changed for this run ("key: value", the sim plugin's; --sim friction=false).
  std::vector<std::string> sim_parameters;
  // The admittance loops compensate the device's identified friction (the thesis's `+ h`) where its preset has
  // a friction file; --no-friction-compensation runs them without.
  bool no_friction_compensation = false;

  [[nodiscard]] ReportOptions report() const { return {out, !no_figures}; }
};

// A subcommand's options, alive as long as the program: CLI11 writes into them while it parses, and the
// documentation test's parse-only mode (HAPTICD_PARSE_ONLY) replaces the callbacks that also hold them.
template <class T>
std::shared_ptr<T> command_options() {
  static std::vector<std::shared_ptr<T>> kept;
  kept.push_back(std::make_shared<T>());
  return kept.back();
}

struct RigDevice;
// The rig's device for these options (experiment/rig.hpp).
RigDevice rig_device(const CommonOptions& options);

// `devices`: the shipped devices the experiment's protocol is written for.
void add_common_options(CLI::App* command, CommonOptions& options,
                        const std::vector<std::string>& devices = {"vishard3"});
// The experiments' scheme list (parse_scheme's spellings) and the mass admittance display renders.
void add_scheme_options(CLI::App* command, std::vector<std::string>& schemes, double& virtual_mass_kg);

}  // namespace hapticd::eval
