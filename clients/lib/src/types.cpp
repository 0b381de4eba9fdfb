#include "hapticd/client/types.hpp"

#include <algorithm>

namespace hapticd::client {

void Name::assign(std::string_view text) noexcept {
  size_ = static_cast<std::uint8_t>(std::min(text.size(), text_.size() - 1));
  std::copy_n(text.data(), size_, text_.data());
  text_[size_] = '\0';
}

std::string_view to_string(Mode mode) noexcept {
  switch (mode) {
    case Mode::starting:
      return "starting";
    case Mode::running:
      return "running";
    case Mode::stopping:
      return "stopping";
    case Mode::safe:
      return "safe";
    case Mode::off:
      return "off";
  }
  return "?";
}

std::vector<std::string> flag_names(std::uint32_t flags) {
  const auto& kNames = kStateFlagNames;
  std::vector<std::string> names;
  for (std::size_t bit = 0; bit < kNames.size(); ++bit)
    if ((flags & (1u << bit)) != 0) names.emplace_back(kNames[bit]);
  for (std::size_t bit = kNames.size(); bit < 32; ++bit)
    if ((flags & (1u << bit)) != 0) names.push_back("bit" + std::to_string(bit));
  return names;
}

std::string_view to_string(EventKind kind) noexcept {
  switch (kind) {
    case EventKind::fault:
      return "fault";
    case EventKind::estop:
      return "estop";
    case EventKind::mode:
      return "mode";
    case EventKind::scheme:
      return "scheme";
    case EventKind::owner:
      return "owner";
    case EventKind::engine_stale:
      return "engine_stale";
    case EventKind::engine_rejected:
      return "engine_rejected";
    case EventKind::recovered:
      return "recovered";
    case EventKind::recording:
      return "recording";
    case EventKind::parameter:
      return "parameter";
  }
  return "?";
}

EngineCommand EngineCommand::coupling(const Pose& proxy, const Twist& proxy_twist, std::uint64_t state_serial) {
  EngineCommand c;
  c.kind = CommandKind::coupling;
  c.state_serial = state_serial;
  c.pose = proxy;
  c.twist = proxy_twist;
  return c;
}

EngineCommand EngineCommand::force(const Wrench& wrench, std::uint64_t state_serial) {
  EngineCommand c;
  c.kind = CommandKind::wrench;
  c.state_serial = state_serial;
  c.wrench = wrench;
  return c;
}

EngineCommand EngineCommand::motion(const Pose& pose, const Twist& twist, std::uint64_t state_serial) {
  EngineCommand c = coupling(pose, twist, state_serial);
  c.kind = CommandKind::motion;
  return c;
}

}  // namespace hapticd::client
