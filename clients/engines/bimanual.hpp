#pragma once
// The bimanual engine's logic (clients/engines/bimanual_engine.cpp; the end-to-end test drives it too):
// an impedance-type engine for a whole device group, run by hapticd::client::Engine (which claims the group). It
// places a virtual box between the hands (resting on a table under it) and answers every group state with one group
// command: each hand's proxy is its grasp point on the box, so the server's virtual coupling pulls each hand towards
// it; the box in turn moves under the same couplings (the devices' own coupling stiffness and damping, read from the
// server), its weight and the table (SharedBody, the shared_object group model's physics).
#include <Eigen/Geometry>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <optional>
#include <span>
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
  BimanualEngine(client::Client& client, model::SharedBodySettings box) : client_(client), box_(box) {}

  // Reads the group's devices' coupling and places the box at the hands of the group's newest state (before the
  // claim: hapticd::client::Engine::connect() found the group). An empty string on success, else what went wrong.
  std::string prepare(const std::string& group, const std::vector<std::string>& devices,
                      std::chrono::duration<double> wait) {
    if (devices.size() != 2) return "the example box is held by two hands";
    const auto first = client_.wait_for_group_state(group, wait);
    if (!first) return "no state of group '" + group + "'";
    for (std::size_t k = 0; k < 2; ++k) devices_[k] = devices[k];
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
    return {};
  }

  // One group state (hapticd::client::Engine's answer, on the receive thread): the box steps under the hands'
  // couplings, each hand's proxy is its grasp point.
  bool answer(std::span<const client::DeviceState* const> states, std::span<client::EngineCommand> commands) {
    if (states.size() != 2) return false;
    std::array<Eigen::Vector3d, 2> position, velocity, force;
    for (std::size_t k = 0; k < 2; ++k) {
      position[k] = states[k]->pose.position;
      velocity[k] = states[k]->twist.linear;
    }
    body_.step(position, velocity, force);
    for (std::size_t k = 0; k < 2; ++k) {
      Pose proxy = states[k]->pose;
      proxy.position = body_.grasp_point(k);
      Twist twist;
      twist.linear = body_.velocity() + body_.angular_velocity().cross(proxy.position - body_.position());
      commands[k] = client::EngineCommand::coupling(proxy, twist, states[k]->serial);
    }
    const BoxReport r = report_of();
    std::lock_guard lock(mutex_);
    report_ = r;
    report_.answered = ++answered_;
    return true;
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
  model::SharedBodySettings box_;
  bool table_below_ = true;
  model::SharedBody body_;  // the receive thread's, after connect()
  std::array<std::string, 2> devices_;
  std::uint64_t answered_ = 0;
  BoxReport start_;
  mutable std::mutex mutex_;
  BoxReport report_;
};

}  // namespace hapticd::examples
