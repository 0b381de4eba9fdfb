#pragma once
// A program of the build run as a child process by a test (an engine, a second client, a server): its output to a
// file, waited for with a limit, signalled (stopped, resumed), and killed when the test ends whatever happened.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

namespace hapticd::test {

class Process {
 public:
  // output: the file its standard output and error go to ("": the test's).
  explicit Process(std::vector<std::string> argv, const std::string& output = "") {
    std::vector<char*> args;
    for (auto& a : argv) args.push_back(a.data());
    args.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    if (!output.empty()) {
      posix_spawn_file_actions_addopen(&actions, 1, output.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      posix_spawn_file_actions_adddup2(&actions, 1, 2);
    }
    if (posix_spawn(&pid_, args[0], &actions, nullptr, args.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&actions);
  }
  // Waits at most `limit_s` for it to exit; its exit code, or -1.
  int wait_exit(double limit_s) {
    const auto start = std::chrono::steady_clock::now();
    while (pid_ > 0 && std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < limit_s) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return -1;
  }
  ~Process() {
    if (pid_ <= 0) return;
    (void)kill(pid_, SIGCONT);
    (void)kill(pid_, SIGKILL);
    (void)waitpid(pid_, nullptr, 0);
  }
  Process(const Process&) = delete;
  Process& operator=(const Process&) = delete;
  [[nodiscard]] bool started() const noexcept { return pid_ > 0; }
  void signal(int sig) const { (void)kill(pid_, sig); }

 private:
  pid_t pid_ = -1;
};

}  // namespace hapticd::test
