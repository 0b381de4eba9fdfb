#pragma once
#include <CLI/CLI.hpp>

namespace hapticd::eval {
// `hapticd-eval tracking`: the inner loops' tracking of a fast path near a singular region (docs/evaluation.md).
void add_tracking_command(CLI::App& app, int& exit_code);
}  // namespace hapticd::eval
