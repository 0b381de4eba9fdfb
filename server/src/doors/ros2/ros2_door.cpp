#include "doors/ros2/ros2_door.hpp"

#include <urdf_parser/urdf_parser.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "gate/gate.hpp"

namespace hapticd::server {
namespace {

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read the robot model " + path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The robot model's root link: the frame robot_state_publisher puts the arm under.
std::string root_link(const std::string& urdf, const std::string& path) {
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(urdf);
  if (!model || !model->getRoot()) throw std::runtime_error("the robot model " + path + " has no root link");
  return model->getRoot()->name;
}

}  // namespace

Ros2Door::Ros2Door(const Ros2Settings& settings, const DdsSettings& network, Gate& gate)
    : settings_(settings),
      period_ns_(static_cast<std::int64_t>(std::llround(1e9 / settings.rate_hz))),
      participant_(dds::ParticipantOptions{settings.domain_id, network.cyclone_config, network.network}) {
  using ros2::Profile;
  using ros2::Writer;
  const dds_entity_t p = participant_.get();
  tf_.emplace(p, "/tf", &tf2_msgs_msg_dds__TFMessage__desc, Profile::tf);
  for (const auto& d : gate.devices()) {
    const DeviceDescription& description = d->device->description();
    const std::string& name = d->device->name();
    const std::string topic = settings.ns + "/" + name + "/";
    auto device = std::make_unique<Device>();
    std::string urdf;
    std::string base_link;
    if (!description.robot_model_file.empty()) {
      urdf = read_file(description.robot_model_file);
      base_link = root_link(urdf, description.robot_model_file);
    }
    device->messages = std::make_unique<ros2::DeviceMessages>(name, description, settings.world_frame, base_link);
    device->pose.emplace(p, topic + "pose", &geometry_msgs_msg_dds__PoseStamped__desc, Profile::sensor_data);
    device->twist.emplace(p, topic + "twist", &geometry_msgs_msg_dds__TwistStamped__desc, Profile::sensor_data);
    device->wrench.emplace(p, topic + "wrench", &geometry_msgs_msg_dds__WrenchStamped__desc, Profile::sensor_data);
    if (description.interface == DeviceInterface::joints)
      device->joints.emplace(p, topic + "joint_states", &sensor_msgs_msg_dds__JointState__desc, Profile::sensor_data);
    else
      device->buttons.emplace(p, topic + "buttons", &sensor_msgs_msg_dds__Joy__desc, Profile::sensor_data);
    if (!urdf.empty()) {
      device->description.emplace(p, topic + "robot_description", &std_msgs_msg_dds__String__desc, Profile::latched);
      const std_msgs_msg_dds__String_ m{urdf.data()};
      if (!device->description->write(&m, dds_time())) failures_.fetch_add(1, std::memory_order_relaxed);
    }
    devices_.push_back(std::move(device));
  }
  commands_ = std::make_unique<ros2::Commands>(settings, p, gate);
  services_ = std::make_unique<ros2::Services>(settings, p, gate);
}

Ros2Door::~Ros2Door() {
  commands_->close();
  services_->close();
}

std::uint64_t Ros2Door::published(std::size_t device) const noexcept {
  return device < devices_.size() ? devices_[device]->published.load(std::memory_order_relaxed) : 0;
}

void Ros2Door::state(std::size_t index, const DeviceSnapshot&, const hapticd_msg_DeviceState& m) {
  if (index >= devices_.size()) return;
  Device& d = *devices_[index];
  const double* o = m.handle_pose.orientation;  // every state's: a wrench command in the handle frame is turned by it
  commands_->set_handle_orientation(index, Eigen::Quaterniond(o[0], o[1], o[2], o[3]).normalized());
  // Decimated on the loop's clock: at most rate_hz, never a burst to catch up.
  if (d.started && m.loop_time_ns < d.next_ns) return;
  d.next_ns =
      d.started && m.loop_time_ns - d.next_ns < period_ns_ ? d.next_ns + period_ns_ : m.loop_time_ns + period_ns_;
  d.started = true;
  const dds_time_t now = dds_time();
  d.messages->fill(m, now);
  // Every topic written even when one write fails; each failure counted (the session's report says how many).
  int failed = !d.pose->write(&d.messages->pose(), now) + !d.twist->write(&d.messages->twist(), now) +
               !d.wrench->write(&d.messages->wrench(), now) + !tf_->write(&d.messages->tf(), now);
  if (d.joints) failed += !d.joints->write(&d.messages->joint_state(), now);
  if (d.buttons) failed += !d.buttons->write(&d.messages->joy(), now);
  if (failed > 0) failures_.fetch_add(static_cast<std::uint64_t>(failed), std::memory_order_relaxed);
  d.published.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace hapticd::server
