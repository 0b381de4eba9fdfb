#pragma once
#include <CLI/CLI.hpp>

namespace hapticd::eval {
// `hapticd-eval backdrivability`: the thesis's backdrivability experiment (docs/evaluation.md).
void add_backdrivability_command(CLI::App& app, int& exit_code);
}  // namespace hapticd::eval
