#pragma once
// The hapticd commands. Each returns the process exit code:
//   0 success; 2 configuration or plugin-loading error; 3 a device faulted during the session;
//   4 any other run-time error (e.g. an output file that cannot be written).
#include <optional>
#include <string>

namespace hapticd::server {

struct RunOptions {
  std::string config_file;
  std::optional<double> duration_s;   // overrides server.duration_s
  std::optional<std::string> clock;   // overrides server.clock
  std::string stats_json;             // write the loop statistics here
  std::string record_csv;             // record every cycle here
  std::optional<int> dds_domain;      // turns the DDS interface on, on this domain (overrides dds.domain_id)
};

inline constexpr int kExitOk = 0;
inline constexpr int kExitConfigError = 2;
inline constexpr int kExitDeviceFault = 3;
inline constexpr int kExitRuntimeError = 4;

int run_session(const RunOptions& options);
int check_config(const std::string& config_file);
int list_plugins(const std::string& config_file);
int describe_plugin(const std::string& name, const std::string& config_file);
int describe_config();

}  // namespace hapticd::server
