#include "doors/ros2/ros2_commands.hpp"

#include <algorithm>
#include <stdexcept>

#include "doors/ros2/ros2_topic.hpp"
#include "gate/gate.hpp"
#include "hapticd/dds/conversion.hpp"
#include "ros2_msg.h"

namespace hapticd::server::ros2 {
namespace {

constexpr const char* kClient = "ros2";

std::int64_t stamp_ns(const builtin_interfaces_msg_dds__Time_& t, std::int64_t received_ns) {
  if (t.sec == 0 && t.nanosec == 0) return received_ns;  // unstamped: as it arrived
  return static_cast<std::int64_t>(t.sec) * 1'000'000'000 + static_cast<std::int64_t>(t.nanosec);
}

}  // namespace

Commands::Commands(const Ros2Settings& settings, dds_entity_t participant, Gate& gate)
    : settings_(settings), gate_(gate), orientation_(gate.devices().size(), Eigen::Quaterniond::Identity()) {
  // A best-effort reader matches publishers of either profile (ROS 2's default, reliable, and sensor data's).
  const dds::Qos q = qos(Profile::sensor_data);
  dds_qset_history(q.get(), DDS_HISTORY_KEEP_LAST, 10);
  for (const auto& d : gate.devices()) {
    const std::string& name = d->device->name();
    if (std::find(settings.commands.begin(), settings.commands.end(), name) != settings.commands.end()) {
      std::lock_guard lock(d->mutex);
      // For the session: ROS 2 topics have no claims. (The config keeps the teleoperation link's device out.)
      if (!d->gate.claim(kClient, PeerId::ros2()))
        throw std::runtime_error("'" + name + "' is held by '" + d->gate.owner() + "': ROS 2 cannot command it");
      d->claim_channel = Sender{PeerId::ros2(), 0};
      d->claimed_ns = 0;
    }
    for (const bool pose : {false, true}) {
      auto r = std::make_unique<Reader>();
      r->self = this;
      r->device = d->index;
      r->pose = pose;
      r->name = name;
      const std::string ros_name = settings.ns + "/" + name + (pose ? "/pose_command" : "/wrench_command");
      const std::string what = "cannot read the ROS 2 topic " + ros_name;
      r->topic =
          make_topic(participant, dds_topic_name(ros_name),
                     pose ? &geometry_msgs_msg_dds__PoseStamped__desc : &geometry_msgs_msg_dds__WrenchStamped__desc,
                     q.get(), what);
      r->reader = make_reader(participant, r->topic, q.get(), what);
      readers_.push_back(std::move(r));
    }
  }
}

Commands::~Commands() { close(); }

void Commands::listen() {
  for (const auto& r : readers_) {
    const dds::Listener listener(dds_create_listener(r.get()));
    dds_lset_data_available(listener.get(), [](dds_entity_t, void* arg) {
      Reader& reader = *static_cast<Reader*>(arg);
      reader.self->take(reader);
    });
    (void)dds_set_listener(r->reader.get(), listener.get());
  }
}

void Commands::close() {
  for (const auto& r : readers_) (void)dds_set_listener(r->reader.get(), nullptr);
}

void Commands::set_handle_orientation(std::size_t device, const Eigen::Quaterniond& q) {
  std::lock_guard lock(orientation_mutex_);
  if (device < orientation_.size()) orientation_[device] = q;
}

void Commands::take(Reader& r) {
  for (;;) {
    void* samples[8] = {};
    dds_sample_info_t infos[8];
    const dds_return_t n = dds_take(r.reader.get(), samples, infos, 8, 8);  // loaned
    if (n <= 0) return;
    for (dds_return_t i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      received_.fetch_add(1, std::memory_order_relaxed);
      const std::int64_t now = dds::wall_clock_ns();
      hapticd_msg_EngineCommand c{};
      dds::set_text(c.device, r.name);
      dds::set_text(c.engine, kClient);
      c.serial = ++r.serial;
      c.anchor.orientation[0] = c.command_pose.orientation[0] = 1.0;
      std::int64_t source_ns = now;
      const auto world = [&](const char* frame) {
        return frame == nullptr || *frame == '\0' || settings_.world_frame == frame;
      };
      if (r.pose) {
        const auto& m = *static_cast<const geometry_msgs_msg_dds__PoseStamped_*>(samples[i]);
        if (!world(m.header.frame_id)) {
          frames_.fetch_add(1, std::memory_order_relaxed);
          continue;
        }
        c.kind = hapticd_msg_COMMAND_COUPLING;
        c.command_pose.position[0] = m.pose.position.x;
        c.command_pose.position[1] = m.pose.position.y;
        c.command_pose.position[2] = m.pose.position.z;
        c.command_pose.orientation[0] = m.pose.orientation.w;  // hapticd's order: w, x, y, z
        c.command_pose.orientation[1] = m.pose.orientation.x;
        c.command_pose.orientation[2] = m.pose.orientation.y;
        c.command_pose.orientation[3] = m.pose.orientation.z;
        source_ns = stamp_ns(m.header.stamp, now);
      } else {
        const auto& m = *static_cast<const geometry_msgs_msg_dds__WrenchStamped_*>(samples[i]);
        Eigen::Vector3d f(m.wrench.force.x, m.wrench.force.y, m.wrench.force.z);
        Eigen::Vector3d t(m.wrench.torque.x, m.wrench.torque.y, m.wrench.torque.z);
        if (!world(m.header.frame_id)) {
          if (r.name + "/handle" != m.header.frame_id) {
            frames_.fetch_add(1, std::memory_order_relaxed);
            continue;
          }
          std::lock_guard lock(orientation_mutex_);
          f = orientation_[r.device] * f;  // the handle's axes into the world's (a NaN stays a NaN: refused below)
          t = orientation_[r.device] * t;
        }
        c.kind = hapticd_msg_COMMAND_WRENCH;
        for (int k = 0; k < 3; ++k) {
          c.wrench[k] = f[k];
          c.wrench[3 + k] = t[k];
        }
        source_ns = stamp_ns(m.header.stamp, now);
      }
      (void)gate_.admit(c, Sender{PeerId::ros2(), static_cast<std::uint64_t>(r.reader.get())}, source_ns);
    }
    (void)dds_return_loan(r.reader.get(), samples, n);
  }
}

}  // namespace hapticd::server::ros2
