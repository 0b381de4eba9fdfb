#include "report.hpp"

#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace hapticd::eval {
namespace {

std::string g_command_line;

// The report program beside this one (hapticd-eval-report: eval/report/eval_report.py as a program of the
// interpreter the Python tools are built for), in the build tree and once installed alike.
std::filesystem::path report_program() {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  const fs::path program = exe.parent_path() / "hapticd-eval-report";
  return fs::is_regular_file(program) ? program : fs::path();
}

}  // namespace

std::filesystem::path write_result(const ReportOptions& options, const std::string& experiment, const Json& result) {
  std::error_code ec;
  std::filesystem::create_directories(options.out_dir, ec);
  if (ec) throw std::runtime_error("cannot create " + options.out_dir.string() + ": " + ec.message());
  const std::filesystem::path file = options.out_dir / (experiment + ".json");
  std::ofstream out(file);
  out << result.dump(1) << "\n";
  out.close();
  if (!out) throw std::runtime_error("cannot write " + file.string());
  return file;
}

bool render_report(const ReportOptions& options) {
  if (!options.figures) return true;
  const std::filesystem::path program = report_program();
  if (program.empty()) {
    fmt::print(stderr, "hapticd-eval: hapticd-eval-report is not beside hapticd-eval: no figures (the JSON is in {})\n",
               options.out_dir.string());
    return false;
  }
  const pid_t pid = fork();
  if (pid == 0) {
    const std::string p = program.string(), dir = options.out_dir.string();
    execl(p.c_str(), p.c_str(), dir.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  if (pid < 0 || waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    fmt::print(stderr,
               "hapticd-eval: the figures were not drawn ({} failed: its first line names the Python it needs, with "
               "Matplotlib); the JSON is in {}\n",
               program.string(), options.out_dir.string());
    return false;
  }
  return true;
}

void publish_result(const ReportOptions& options, const std::string& experiment, const Json& result) {
  fmt::print("results: {}\n", write_result(options, experiment, result).string());
  render_report(options);
}

std::string command_line() { return g_command_line; }

void set_command_line(int argc, char** argv) {
  g_command_line.clear();
  for (int i = 0; i < argc; ++i) {
    if (i > 0) g_command_line += ' ';
    const std::string a = i == 0 ? std::string("hapticd-eval") : std::string(argv[i]);
    g_command_line += a.find(' ') == std::string::npos ? a : "'" + a + "'";
  }
}

}  // namespace hapticd::eval
