#pragma once
// The bimanual engine's logic (clients/engines/bimanual_engine.cpp; the end-to-end test drives it too):
// an impedance-type engine for a whole device group. It claims the group, places a virtual box between the hands
// (resting on a table under it), and answers every group state with one group command: each hand's proxy is its
// grasp point on the box, so the server's virtual coupling pulls each hand towards it; the box in turn moves under
// the same couplings (the devices' own coupling stiffness and damping, read from the server), its weight and the
// table (SharedBody, the shared_object group model's physics).
#include <Eigen/Geometry>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "hapticd/client/client.hpp"
#include "hapticd/model/shared_body.hpp"

namespace hapticd::examples {

struct BoxReport {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double yaw_deg = 0.0;
  double internal_force_n = 0.0;
  double table_force_n = 0.0;
  std::uint64_t answered = 0;
};

class BimanualEngine {
 public:
  BimanualEngine(client::Client& client, std::string group, model::SharedBodySettings box)
      : client_(client), group_(std::move(group)), box_(box) {}
  ~BimanualEngine() { client_.on_group_state({}); }
  BimanualEngine(const BimanualEngine&) = delete;
  BimanualEngine& operator=(const BimanualEngine&) = delete;

  // Finds and claims the group, reads its devices' coupling, places the box; then answers every group state.
  // An empty string on success, else what went wrong.
  std::string connect(std::chrono::duration<double> wait) {
    const auto described = client_.wait_for_group(group_, wait);
    if (!described) return "no group '" + group_ + "'";
    if (described->devices.size() != 2) return "the example box is held by two hands";
    const auto first = client_.wait_for_group_state(group_, wait);
    if (!first) return "no state of group '" + group_ + "'";
    for (int k = 0; k < 2; ++k) devices_[static_cast<std::size_t>(k)] = described->devices[static_cast<std::size_t>(k)];
    // The box couples to the hands as the devices' virtual coupling does: the same spring and damper.
    const client::Reply k = client_.get_parameter(devices_[0], "virtual_model.coupling_stiffness_n_per_m", wait);
    const client::Reply b = client_.get_parameter(devices_[0], "virtual_model.coupling_damping_n_s_per_m", wait);
    if (!k.accepted || k.values.size() != 1 || !b.accepted || b.values.size() != 1)
      return "device '" + devices_[0] + "' has no virtual coupling (an admittance model with coupling: true)";
    box_.coupling_stiffness_n_per_m = k.values[0];
    box_.coupling_damping_n_s_per_m = b.values[0];
    box_.table_height_m = table_below_ ? hands_z(*first) - 0.5 * box_.size_m.z() : box_.table_height_m;
    body_.configure(box_, 1.0 / first->states[0].loop.rate_hz);
    // Between the hands, level, its x axis from the first hand to the second; each hand grasps it where it is.
    const Eigen::Vector3d h0 = first->states[0].pose.position;
    const Eigen::Vector3d h1 = first->states[1].pose.position;
    Pose pose;
    pose.position = 0.5 * (h0 + h1);
    pose.orientation =
        Eigen::Quaterniond(Eigen::AngleAxisd(std::atan2(h1.y() - h0.y(), h1.x() - h0.x()), Eigen::Vector3d::UnitZ()));
    const std::array<Eigen::Vector3d, 2> grasp = {pose.orientation.conjugate() * (h0 - pose.position),
                                                  pose.orientation.conjugate() * (h1 - pose.position)};
    body_.reset(pose, grasp);
    start_ = report_of();
    if (!client_.claim_group(group_, wait).accepted) return "group '" + group_ + "' is claimed by another engine";
    client_.on_group_state([this](const client::GroupState& g) { answer(g); });
    return {};
  }
  // The table under the box at the hands' height at the start (default), or at this height (world z).
  void set_table_height(double z) {
    table_below_ = false;
    box_.table_height_m = z;
  }

  [[nodiscard]] BoxReport report() const {
    std::lock_guard lock(mutex_);
    return report_;
  }
  [[nodiscard]] const BoxReport& start() const noexcept { return start_; }

 private:
  static double hands_z(const client::GroupState& g) {
    return 0.5 * (g.states[0].pose.position[2] + g.states[1].pose.position[2]);
  }

  void answer(const client::GroupState& g) {
    if (g.device_count != 2 || g.serial <= last_serial_) return;  // (a repeated state: answered already)
    last_serial_ = g.serial;
    std::array<Eigen::Vector3d, 2> position, velocity, force;
    for (std::size_t k = 0; k < 2; ++k) {
      position[k] = g.states[k].pose.position;
      velocity[k] = g.states[k].twist.linear;
    }
    body_.step(position, velocity, force);
    std::array<client::DeviceCommand, 2> commands;
    for (std::size_t k = 0; k < 2; ++k) {
      Pose proxy = g.states[k].pose;
      proxy.position = body_.grasp_point(k);
      Twist twist;
      twist.linear = body_.velocity() + body_.angular_velocity().cross(proxy.position - body_.position());
      commands[k] = {client::Name(devices_[k]), client::EngineCommand::coupling(proxy, twist, g.states[k].serial)};
    }
    (void)client_.send_group(group_, commands);
    const BoxReport r = report_of();
    std::lock_guard lock(mutex_);
    report_ = r;
    report_.answered = ++answered_;
  }

  BoxReport report_of() const {
    BoxReport r;
    r.position = body_.position();
    const Eigen::Vector3d x = body_.orientation() * Eigen::Vector3d::UnitX();
    r.yaw_deg = std::atan2(x.y(), x.x()) * 180.0 / 3.14159265358979323846;
    r.internal_force_n = body_.internal_force_n();
    r.table_force_n = body_.table_force().z();
    return r;
  }

  client::Client& client_;
  std::string group_;
  model::SharedBodySettings box_;
  bool table_below_ = true;
  model::SharedBody body_;  // the receive thread's, after connect()
  std::array<std::string, 2> devices_;
  std::uint64_t last_serial_ = 0, answered_ = 0;
  BoxReport start_;
  mutable std::mutex mutex_;
  BoxReport report_;
};

}  // namespace hapticd::examples
