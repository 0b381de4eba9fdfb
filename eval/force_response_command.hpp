#pragma once
#include <CLI/CLI.hpp>

namespace hapticd::eval {
// `hapticd-eval force-response`: the thesis's dynamic force precision experiment (docs/evaluation.md).
void add_force_response_command(CLI::App& app, int& exit_code);
}  // namespace hapticd::eval
