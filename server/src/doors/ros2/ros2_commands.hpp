#pragma once
// The ROS 2 door's command path (docs/ros2.md, "Commands"): for every device, readers of
//   <ns>/<device>/wrench_command  geometry_msgs/msg/WrenchStamped  a wrench on the handle (the engine's WRENCH)
//   <ns>/<device>/pose_command    geometry_msgs/msg/PoseStamped    a coupling proxy (the engine's COUPLING)
// taken on Cyclone's receive threads (a listener, as the DDS door's commands) and put through the gate like every
// door's (Gate::admit: owner, order, freshness, bounds, non-finite values; the hand-over to the loop; deadlines, fades
// and stop latches after it). ROS 2 topics have no claims: the devices the `ros2` section gives to ROS are claimed
// by ROS for the session (client "ros2"); a command to any other device is refused by the gate (not the owner) and
// counted. A wrench in the world frame or the handle's ("" is the world), a pose in the world frame; any other frame
// id is refused and counted. A stamp of zero is the time the command arrived; otherwise the gate's freshness rule
// holds it to the server's clock.
#include <dds/dds.h>

#include <Eigen/Geometry>
#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "config/ros2_settings.hpp"
#include "hapticd/dds/entity.hpp"

namespace hapticd::server {

class Gate;

namespace ros2 {

class Commands {
 public:
  // Claims the given devices for ROS and makes the readers (no command flows before listen()).
  Commands(const Ros2Settings& settings, dds_entity_t participant, Gate& gate);
  ~Commands();
  Commands(const Commands&) = delete;
  Commands& operator=(const Commands&) = delete;

  void listen();
  void close();
  // The publisher thread: the handle's newest orientation (a wrench in the handle frame is turned by it).
  void set_handle_orientation(std::size_t device, const Eigen::Quaterniond& q);

  [[nodiscard]] std::uint64_t received() const noexcept { return received_.load(std::memory_order_relaxed); }
  // Refused here, before the gate (a frame it does not know); the gate counts its own refusals.
  [[nodiscard]] std::uint64_t refused_frames() const noexcept { return frames_.load(std::memory_order_relaxed); }

 private:
  struct Reader {
    Commands* self = nullptr;
    std::size_t device = 0;
    bool pose = false;  // pose_command, else wrench_command
    std::string name;   // the device's
    dds::Entity topic, reader;
    std::uint64_t serial = 0;  // ours: ROS messages carry none (one receive thread per reader at a time)
  };
  void take(Reader& r);

  Ros2Settings settings_;
  Gate& gate_;
  std::vector<std::unique_ptr<Reader>> readers_;
  std::mutex orientation_mutex_;
  std::vector<Eigen::Quaterniond> orientation_;  // by device
  std::atomic<std::uint64_t> received_{0}, frames_{0};
};

}  // namespace ros2
}  // namespace hapticd::server
