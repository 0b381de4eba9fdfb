#pragma once
#include <CLI/CLI.hpp>

namespace hapticd::eval {
// `hapticd-eval z-width`: the range of virtual walls each scheme renders stably and passively (docs/evaluation.md).
void add_z_width_command(CLI::App& app, int& exit_code);
}  // namespace hapticd::eval
