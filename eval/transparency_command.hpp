#pragma once
#include <CLI/CLI.hpp>

namespace hapticd::eval {
// `hapticd-eval transparency`: Table 5.1's inertia and friction indices over the workspace (docs/evaluation.md).
void add_transparency_command(CLI::App& app, int& exit_code);
}  // namespace hapticd::eval
