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
  // Not a mistake of the session's: a device, its vendor's library or service is not there (DeviceUnavailable).
  [[nodiscard]] bool device_unavailable() const noexcept { return device_unavailable_; }
  ConfigError& set_device_unavailable() noexcept {
    device_unavailable_ = true;
    return *this;
  }

 private:
  std::string file_;
  int line_;
  std::string key_;
  std::string message_;
  bool device_unavailable_ = false;
};

}  // namespace hapticd::server
