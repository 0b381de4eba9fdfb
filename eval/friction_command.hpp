#pragma once
#include <CLI/CLI.hpp>

namespace hapticd::eval {
// `hapticd-eval friction`: the friction identification against the simulator's truth (docs/evaluation.md).
void add_friction_command(CLI::App& app, int& exit_code);
}  // namespace hapticd::eval
