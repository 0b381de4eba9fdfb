#pragma once
#include <stdexcept>
#include <string>

namespace hapticd::server {

// A configuration error that says where: "session.yaml:12: devices[0].controller.parameters.kp: value -3 is
// below the minimum 0". line is 1-based; 0 when the error is about the file as a whole.
class ConfigError : public std::runtime_error {
 public:
  ConfigError(std::string file, int line, std::string key, std::string message);

  [[nodiscard]] const std::string& file() const noexcept { return file_; }
  [[nodiscard]] int line() const noexcept { return line_; }
  [[nodiscard]] const std::string& key() const noexcept { return key_; }
  [[nodiscard]] const std::string& message() const noexcept { return message_; }

 private:
  std::string file_;
  int line_;
  std::string key_;
  std::string message_;
};

}  // namespace hapticd::server
