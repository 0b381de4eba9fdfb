#pragma once
#include <CLI/CLI.hpp>

namespace hapticd::eval {
// `hapticd-eval teleoperation`: a stiff wall and free motion through a delayed, lossy link, with and without
// passivity control (docs/teleoperation.md, "Evaluation").
void add_teleoperation_command(CLI::App& app, int& exit_code);
}  // namespace hapticd::eval
