#include "gate/messages.hpp"

#include <algorithm>

#include "hapticd/dds/conversion.hpp"
#include "session/device_requests.hpp"
#include "session/state_flags.hpp"

namespace hapticd::server {

// The IDL's constants and the server's own (session/state_flags.hpp) are one definition.
static_assert(hapticd_msg_FLAG_TORQUE_SATURATED == state_flag::torque_saturated);
static_assert(hapticd_msg_FLAG_ENGINE_ACTIVE == state_flag::engine_active);
static_assert(hapticd_msg_FLAG_ENGINE_STALE == state_flag::engine_stale);
static_assert(hapticd_msg_FLAG_ESTOP == state_flag::estop);
static_assert(hapticd_msg_FLAG_FAULT == state_flag::fault);
static_assert(hapticd_msg_FLAG_SWITCHING == state_flag::switching);
static_assert(hapticd_msg_FLAG_SAFE_DAMPING == state_flag::safe_damping);
static_assert(hapticd_msg_FLAG_LIMIT_ENGAGED == state_flag::limit_engaged);
static_assert(hapticd_msg_FLAG_RENDER_LIMITED == state_flag::render_limited);
static_assert(hapticd_msg_FLAG_THERMAL_DERATING == state_flag::thermal_derating);
static_assert(hapticd_msg_FLAG_PASSIVITY_CONTROL == state_flag::passivity_control);
static_assert(hapticd_msg_MODE_STARTING == static_cast<int>(DeviceMode::starting));
static_assert(hapticd_msg_MODE_RUNNING == static_cast<int>(DeviceMode::running));
static_assert(hapticd_msg_MODE_STOPPING == static_cast<int>(DeviceMode::stopping));
static_assert(hapticd_msg_MODE_SAFE == static_cast<int>(DeviceMode::safe));
static_assert(hapticd_msg_MODE_OFF == static_cast<int>(DeviceMode::off));

hapticd_msg_DeviceMode mode_of(const DeviceSnapshot& s) noexcept {
  return static_cast<hapticd_msg_DeviceMode>(device_mode(s));
}

std::uint32_t flags_of(const DeviceSnapshot& s) noexcept { return state_flags(s); }

hapticd_msg_DeviceState state_message(const DeviceSnapshot& s, const StateLabels& labels) noexcept {
  hapticd_msg_DeviceState m{};
  dds::set_text(m.device, labels.device);
  m.serial = labels.serial;
  m.cycle = s.cycle;
  m.loop_time_ns = s.time_ns;
  dds::to_msg(s.handle_pose, m.handle_pose);
  dds::to_msg(s.handle_twist, m.twist);
  dds::to_msg(s.operator_wrench, m.operator_wrench);
  dds::to_msg(s.environment_wrench, m.environment_wrench);
  dds::to_msg(s.target_pose, m.target_pose);
  m.dof = static_cast<std::int32_t>(s.position.size());
  for (Eigen::Index i = 0; i < s.position.size() && i < hapticd_msg_MAX_JOINTS; ++i) {
    m.position[i] = s.position[i];
    m.velocity[i] = i < s.velocity.size() ? s.velocity[i] : 0.0;
    m.torque[i] = i < s.torque.size() ? s.torque[i] : 0.0;
  }
  m.buttons = s.buttons;
  m.gripper = s.gripper;
  m.mode = mode_of(s);
  m.flags = flags_of(s);
  dds::set_text(m.fault, s.fault == DeviceFault::none ? std::string_view() : fault_code(s.fault));
  dds::set_text(m.scheme, labels.scheme);
  dds::set_text(m.owner, labels.owner);
  m.engine_serial = s.engine_sequence;
  m.loop = labels.loop;
  return m;
}

hapticd_msg_DeviceDescription description_message(const DeviceRequests& s, double rate_hz,
                                                  const std::optional<Pose>& start_pose) {
  const DeviceDescription& desc = s.description();
  hapticd_msg_DeviceDescription m{};
  dds::set_text(m.device, s.name());
  m.data_model_version = hapticd_msg_VERSION;
  dds::set_text(m.device_plugin, s.chain().device.descriptor->name);
  m.simulated = desc.simulated;
  m.rate_hz = rate_hz;
  m.dof = desc.dof();
  for (int i = 0; i < desc.dof() && i < hapticd_msg_MAX_JOINTS; ++i) {
    const JointDescription& j = desc.joints[static_cast<std::size_t>(i)];
    dds::set_text(m.joint_names[i].text, j.name);
    m.position_min[i] = j.position_min;
    m.position_max[i] = j.position_max;
    m.velocity_max[i] = j.velocity_max;
    m.torque_peak[i] = j.torque_peak_nm;
    m.torque_continuous[i] = j.torque_continuous_nm;
  }
  dds::set_text(m.base_frame, "world");
  dds::to_msg(desc.base_pose, m.base_pose);
  dds::set_text(m.handle_frame, desc.handle_frame);
  if (start_pose) dds::to_msg(*start_pose, m.start_pose);
  const SafetySettings& safety = s.chain().safety;
  for (int k = 0; k < 3; ++k) {
    m.workspace_min[k] = safety.workspace_min_m[static_cast<std::size_t>(k)];
    m.workspace_max[k] = safety.workspace_max_m[static_cast<std::size_t>(k)];
  }
  const auto& schemes = s.chain().schemes;
  m.scheme_count = static_cast<std::int32_t>(std::min<std::size_t>(schemes.size(), hapticd_msg_MAX_SCHEMES));
  for (std::int32_t k = 0; k < m.scheme_count; ++k) {
    const SchemeChain& sc = schemes[static_cast<std::size_t>(k)];
    dds::set_text(m.schemes[k].text, sc.name);
    dds::set_text(m.scheme_virtual_model[k].text,
                  sc.virtual_model ? std::string_view(sc.virtual_model->descriptor->name) : "");
  }
  m.command_deadline_s = s.chain().engine_deadline_s;
  m.command_fade_s = s.chain().engine_fade_s;
  m.handle_device = desc.interface == DeviceInterface::handle;
  m.handle_dof = m.handle_device ? desc.handle.degrees_of_freedom() : 0;
  m.has_gripper = m.handle_device && desc.handle.has_gripper;
  m.button_count = m.handle_device ? desc.handle.buttons : 0;
  return m;
}

void fill_fault_report(hapticd_msg_FaultReport& m, std::string_view device, int dof,
                       const FaultReport& report) noexcept {
  m = hapticd_msg_FaultReport{};
  dds::set_text(m.device, device);
  m.serial = report.serial;
  dds::set_text(m.fault, fault_code(report.fault));
  std::string message(to_string(report.fault));
  if (report.reason[0] != '\0') message += ": " + std::string(report.reason.data());
  dds::set_text(m.message, message);
  m.cycle = report.cycle;
  m.loop_time_ns = report.time_ns;
  m.dof = dof;
  m.record_count = static_cast<std::int32_t>(std::min<std::uint32_t>(report.count, hapticd_msg_MAX_HISTORY));
  for (std::int32_t k = 0; k < m.record_count; ++k) {
    const HistoryRecord& r = report.records[static_cast<std::size_t>(k)];
    hapticd_msg_CycleRecord& o = m.records[k];
    o.cycle = r.cycle;
    o.loop_time_ns = r.time_ns;
    for (Eigen::Index i = 0; i < r.position.size() && i < hapticd_msg_MAX_JOINTS; ++i) {
      o.position[i] = r.position[i];
      o.velocity[i] = i < r.velocity.size() ? r.velocity[i] : 0.0;
      o.torque[i] = i < r.torque.size() ? r.torque[i] : 0.0;
    }
    for (int i = 0; i < 3; ++i) {
      o.handle_position[i] = r.handle_position[i];
      o.handle_velocity[i] = r.handle_velocity[i];
      o.operator_force[i] = r.operator_force[i];
      o.environment_force[i] = r.environment_force[i];
    }
    o.flags = r.flags;
  }
}

PublishedView view_of(const DeviceSnapshot& s) noexcept {
  return PublishedView{mode_of(s), s.fault, s.faults, s.scheme, s.engine_stale, s.fault_reason};
}

std::vector<EventText> events_between(const PublishedView& before, const PublishedView& now,
                                      const std::vector<std::string>& scheme_names) {
  static constexpr const char* kModes[] = {"starting", "running", "stopping", "safe", "off"};
  std::vector<EventText> events;
  if (now.mode != before.mode) {
    const auto mode = static_cast<std::size_t>(now.mode);
    const std::string name = mode < 5 ? kModes[mode] : "?";
    events.push_back({hapticd_msg_EVENT_MODE, name, "mode: " + name});
  }
  if (now.fault != before.fault || now.faults != before.faults) {
    if (now.fault == DeviceFault::none) {
      if (before.fault != DeviceFault::none)
        events.push_back({hapticd_msg_EVENT_RECOVERED, std::string(fault_code(before.fault)),
                          "the device left its safe mode on request"});
    } else {
      events.push_back({now.fault == DeviceFault::emergency_stop ? hapticd_msg_EVENT_ESTOP : hapticd_msg_EVENT_FAULT,
                        std::string(fault_code(now.fault)),
                        std::string(to_string(now.fault)) +
                            (now.fault_reason != nullptr ? " (" + std::string(now.fault_reason) + ")" : std::string()) +
                            ": the device is in its safe mode (damping, then zero torque); "
                            "its history is on the fault report topic"});
    }
  }
  if (now.scheme != before.scheme && now.scheme >= 0 && static_cast<std::size_t>(now.scheme) < scheme_names.size()) {
    const std::string& name = scheme_names[static_cast<std::size_t>(now.scheme)];
    events.push_back({hapticd_msg_EVENT_SCHEME, name, "switched to scheme " + name});
  }
  if (now.stale && !before.stale)
    events.push_back({hapticd_msg_EVENT_ENGINE_STALE, "deadline", "engine input missed its deadline: forces fade out"});
  return events;
}

}  // namespace hapticd::server
