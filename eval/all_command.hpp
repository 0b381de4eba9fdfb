#pragma once
#include <CLI/CLI.hpp>

namespace hapticd::eval {
// `hapticd-eval all`: every experiment of the chapter in turn, one report (docs/evaluation.md).
void add_all_command(CLI::App& app, int& exit_code);
}  // namespace hapticd::eval
