#pragma once
// Where an experiment's results go: <out>/<experiment>.json (the figures, the thesis's published values beside
// them, the command that reproduces them, one run's session file), then the figures (PNG) and one
// self-contained HTML report over every result in the folder, drawn by hapticd-eval-report (eval/report/eval_report.py,
// Matplotlib).
#include <filesystem>
#include <string>

#include "json.hpp"

namespace hapticd::eval {

struct ReportOptions {
  std::filesystem::path out_dir = "eval-results";
  bool figures = true;  // draw the PNG figures and the HTML report after the JSON
};

// Writes <out>/<experiment>.json (creating the folder); returns its path. Throws std::runtime_error naming the
// file when it cannot be written.
std::filesystem::path write_result(const ReportOptions& options, const std::string& experiment, const Json& result);

// Draws the figures and report.html for every result in the folder with hapticd-eval-report, the program beside
// this one (it names its interpreter). Returns false (with the reason on standard error) when that is not
// possible here; the JSON is written either way.
bool render_report(const ReportOptions& options);

// Writes the result (write_result), says where, and draws the report (render_report).
void publish_result(const ReportOptions& options, const std::string& experiment, const Json& result);

// The command line this program was started with (for "reproduce with").
std::string command_line();
void set_command_line(int argc, char** argv);

}  // namespace hapticd::eval
