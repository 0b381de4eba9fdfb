#pragma once
// The ROS 2 door (docs/ros2.md): the session's devices on ROS 2's wire, for `ros2 topic echo`, rviz2 and ROS 2
// nodes - a participant of its own in the ROS domain (loopback unless the `dds` section's network says otherwise)
// that publishes, for each device, at ros2.rate_hz (every state the gate hands on, decimated):
//   <ns>/<device>/pose          geometry_msgs/msg/PoseStamped   the handle in the world      sensor data QoS
//   <ns>/<device>/twist         geometry_msgs/msg/TwistStamped  the handle's, handle frame   sensor data QoS
//   <ns>/<device>/wrench        geometry_msgs/msg/WrenchStamped the operator's, handle frame sensor data QoS
//   <ns>/<device>/joint_states  sensor_msgs/msg/JointState      a joint device's joints      sensor data QoS
//   <ns>/<device>/buttons       sensor_msgs/msg/Joy             a handle device's buttons    sensor data QoS
//   /tf                         tf2_msgs/msg/TFMessage          world -> base -> handle      tf2_ros's QoS
//   <ns>/<device>/robot_description  std_msgs/msg/String  the URDF, once          transient local
// and reads each device's wrench_command and pose_command (ros2_commands.hpp: through the gate; the devices the
// section gives to ROS are claimed by ROS for the session) and answers its estop and recover services
// (ros2_services.hpp: std_srvs/srv/Trigger, through the request dispatcher). The types are ROS 2's own definitions
// through rosidl (idl/ros2/; ros2_msg.h); the topics and QoS are in ros2_topic.hpp, the messages in ros2_messages.hpp.
// It writes on the gate's publisher thread, never on the loop.
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "config/ros2_settings.hpp"
#include "config/session_config.hpp"
#include "doors/ros2/ros2_commands.hpp"
#include "doors/ros2/ros2_messages.hpp"
#include "doors/ros2/ros2_services.hpp"
#include "doors/ros2/ros2_topic.hpp"
#include "gate/door.hpp"
#include "hapticd/dds/participant.hpp"

namespace hapticd::server {

class Gate;

class Ros2Door final : public Door {
 public:
  // Throws std::runtime_error (a DDS error, an unreadable robot model) naming what failed.
  Ros2Door(const Ros2Settings& settings, const DdsSettings& network, Gate& gate);
  ~Ros2Door() override;

  [[nodiscard]] DoorKind kind() const noexcept override { return DoorKind::ros2; }
  // ROS's claims last the session: its channel is always open, its peer always alive.
  [[nodiscard]] bool channel_open(const Sender& s) const override { return s.peer.door == DoorKind::ros2; }
  [[nodiscard]] bool alive(const PeerId& p) override { return p.door == DoorKind::ros2; }
  void state(std::size_t device, const DeviceSnapshot&, const hapticd_msg_DeviceState& m) override;
  void answer_requests(RequestDispatcher& dispatcher) override { services_->answer(dispatcher); }
  void start() override {
    commands_->listen();
    services_->listen();
  }
  void stop() override {
    commands_->close();
    services_->close();
  }

  // For tests and the session's report: states published per device, and writes that failed.
  [[nodiscard]] std::uint64_t published(std::size_t device) const noexcept;
  [[nodiscard]] std::uint64_t write_failures() const noexcept { return failures_.load(std::memory_order_relaxed); }
  [[nodiscard]] const ros2::Commands& commands() const noexcept { return *commands_; }

 private:
  struct Device {
    std::unique_ptr<ros2::DeviceMessages> messages;
    std::optional<ros2::Writer> pose, twist, wrench, joints, buttons, description;
    std::int64_t next_ns = 0;
    bool started = false;
    std::atomic<std::uint64_t> published{0};
  };

  Ros2Settings settings_;
  std::int64_t period_ns_;
  dds::Participant participant_;
  std::optional<ros2::Writer> tf_;
  std::vector<std::unique_ptr<Device>> devices_;  // by the gate's device index
  std::unique_ptr<ros2::Commands> commands_;
  std::unique_ptr<ros2::Services> services_;
  std::atomic<std::uint64_t> failures_{0};
};

}  // namespace hapticd::server
