#pragma once
// The hapticd commands. Each returns the process exit code:
//   0 success; 2 configuration or plugin-loading error; 3 a device faulted during the session (also when it
//   recovered);
//   4 any other run-time error (e.g. an output file that cannot be written, a resource that cannot be had at
//   start-up); 5 the recording failed (a write, sync or close: cycles were lost) - 3 takes precedence.
#include <optional>
#include <string>
#include <vector>

namespace hapticd::server {

struct RunOptions {
  std::string config_file;
  std::optional<double> duration_s;  // overrides server.duration_s
  std::optional<std::string> clock;  // overrides server.clock
  std::string stats_json;            // write the loop statistics here
  std::string record_file;           // record every cycle here (HDF5, docs/recording.md)
  std::optional<int> dds_domain;     // turns the DDS interface on, on this domain (overrides dds.domain_id)
  std::vector<std::string> sets;     // --set key.path=value: overrides of the session file (config_overrides)
  bool busy_machine = false;         // simulated devices' loop watchdogs loosened (a shared development machine)
};

inline constexpr int kExitOk = 0;
inline constexpr int kExitConfigError = 2;
inline constexpr int kExitDeviceFault = 3;
inline constexpr int kExitRuntimeError = 4;
inline constexpr int kExitRecordingFailed = 5;

int run_session(const RunOptions& options);
int check_config(const std::string& config_file, const std::vector<std::string>& sets = {});
int list_plugins(const std::string& config_file);
int describe_plugin(const std::string& name, const std::string& config_file);
int describe_config(const std::string& config_file);

}  // namespace hapticd::server
