#pragma once
#include <CLI/CLI.hpp>

namespace hapticd::eval {
// `hapticd-eval minimum-inertia`: the smallest stable virtual mass per scheme and direction (docs/evaluation.md).
void add_minimum_inertia_command(CLI::App& app, int& exit_code);
}  // namespace hapticd::eval
