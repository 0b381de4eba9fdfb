#pragma once
// hapticd-eval output-capability: worst-direction force, velocity and acceleration over a workspace grid.
#include <CLI/CLI.hpp>

namespace hapticd::eval {

void add_output_capability_command(CLI::App& app, int& exit_code);

}  // namespace hapticd::eval
