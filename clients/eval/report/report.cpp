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

std::filesystem::path find_report_script() {
  namespace fs = std::filesystem;
  std::vector<fs::path> candidates;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) candidates.push_back(exe.parent_path().parent_path() / HAPTICD_INSTALL_DATADIR / "hapticd" / "scripts");
  candidates.emplace_back(HAPTICD_SOURCE_SCRIPTS_DIR);
  for (const fs::path& dir : candidates) {
    if (fs::is_regular_file(dir / "eval_report.py")) return dir / "eval_report.py";
  }
  return {};
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
  const std::filesystem::path script = find_report_script();
  if (script.empty()) {
    fmt::print(stderr, "hapticd-eval: eval_report.py not found: no figures (the JSON is in {})\n",
               options.out_dir.string());
    return false;
  }
  // The interpreter: $HAPTICD_PYTHON, else python3 on the PATH.
  const char* env = std::getenv("HAPTICD_PYTHON");
  const std::string python = env != nullptr && *env != '\0' ? env : "python3";
  const pid_t pid = fork();
  if (pid == 0) {
    const std::string s = script.string(), dir = options.out_dir.string();
    execlp(python.c_str(), python.c_str(), s.c_str(), dir.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  if (pid < 0 || waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    fmt::print(stderr,
               "hapticd-eval: the figures were not drawn ({} {} failed: python3 with matplotlib is needed, "
               "Debian's python3-matplotlib; HAPTICD_PYTHON names another interpreter); the JSON is in {}\n",
               python, script.string(), options.out_dir.string());
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
