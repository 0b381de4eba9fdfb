#pragma once
#include <CLI/CLI.hpp>

namespace hapticd::eval {
// `hapticd-eval force-gain`: the largest force-feedback gain impedance display renders stably, per direction, under
// the standardized operator loads (docs/evaluation.md).
void add_force_gain_command(CLI::App& app, int& exit_code);
}  // namespace hapticd::eval
