// shared_object: bimanual coupling (docs/multi-device.md, "Bimanual coupling"). The hands of a group hold one
// virtual rigid box (SharedBody: mass, inertia, gravity, a table plane) through a spring-damper each; the box is
// placed between the hands at the group's first cycle, its x axis along the line from the first hand to the second
// (horizontal), and each hand grasps it where it is. Every cycle the box moves under the hands' couplings, its
// weight and the table, and each hand feels its coupling's reaction.
// Run-time request "state": the box's position (3), orientation quaternion w x y z (4), the internal force
// between the first two hands (N, positive squeezes) and the table's vertical force (N).
#include <Eigen/Geometry>
#include <array>
#include <atomic>
#include <cmath>

#include "hapticd/group_model.hpp"
#include "hapticd/model/shared_body.hpp"
#include "hapticd/plugin.hpp"
#include "hapticd/realtime/latest_value.hpp"

namespace hapticd::group_models {
using model::SharedBody;
using model::SharedBodySettings;
namespace {

struct ObjectState {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  double internal_force_n = 0.0;
  double table_force_n = 0.0;
};

class SharedObjectModel final : public GroupModel {
 public:
  static ParameterSchema parameter_schema() {
    ParameterSchema s;
    const SharedBodySettings d;
    s.real("mass_kg", "the object's mass").unit("kg").greater_than(0.0).maximum(100.0).default_value(d.mass_kg);
    s.real_vector("size_m", "the box's edges along its x (from the first hand to the second), y and z")
        .unit("m")
        .size(3)
        .default_value(std::vector<double>{d.size_m.x(), d.size_m.y(), d.size_m.z()});
    s.real_vector("gravity_m_s2", "gravity, world frame")
        .unit("m/s^2")
        .size(3)
        .default_value(std::vector<double>{d.gravity.x(), d.gravity.y(), d.gravity.z()});
    s.real("coupling_stiffness_n_per_m", "each hand's spring to its grasp point")
        .unit("N/m")
        .greater_than(0.0)
        .maximum(1e5)
        .default_value(d.coupling_stiffness_n_per_m);
    s.real("coupling_damping_n_s_per_m", "each hand's damper to its grasp point")
        .unit("N s/m")
        .minimum(0.0)
        .maximum(1e3)
        .default_value(d.coupling_damping_n_s_per_m);
    s.boolean("table", "a table plane (z = table_height_m, world) the object rests on").default_value(d.table);
    s.real("table_height_m", "the table's height, world z").unit("m").default_value(d.table_height_m);
    s.real("table_stiffness_n_per_m", "contact spring per corner")
        .unit("N/m")
        .greater_than(0.0)
        .maximum(1e6)
        .default_value(d.table_stiffness_n_per_m);
    s.real("table_damping_n_s_per_m", "contact damper per corner")
        .unit("N s/m")
        .minimum(0.0)
        .maximum(1e4)
        .default_value(d.table_damping_n_s_per_m);
    s.real("table_friction", "Coulomb friction coefficient on the table")
        .minimum(0.0)
        .maximum(2.0)
        .default_value(d.table_friction);
    s.integer("substeps", "integration steps per loop period")
        .minimum(1)
        .maximum(50)
        .default_value(std::int64_t{d.substeps});
    return s;
  }

  void configure(const Parameters& p, const GroupModelContext& context) override {
    if (context.devices.size() < 2 || context.devices.size() > SharedBody::kMaxHands)
      throw ParameterError(
          "", "a shared object is held by 2 to 8 hands (the group has " + std::to_string(context.devices.size()) + ")");
    SharedBodySettings s;
    s.mass_kg = p.real("mass_kg");
    const auto& size = p.real_vector("size_m");
    s.size_m = Eigen::Vector3d(size[0], size[1], size[2]);
    if (!(s.size_m.minCoeff() > 0.0)) throw ParameterError("size_m", "every edge must be positive");
    const auto& g = p.real_vector("gravity_m_s2");
    s.gravity = Eigen::Vector3d(g[0], g[1], g[2]);
    s.coupling_stiffness_n_per_m = p.real("coupling_stiffness_n_per_m");
    s.coupling_damping_n_s_per_m = p.real("coupling_damping_n_s_per_m");
    s.table = p.boolean("table");
    s.table_height_m = p.real("table_height_m");
    s.table_stiffness_n_per_m = p.real("table_stiffness_n_per_m");
    s.table_damping_n_s_per_m = p.real("table_damping_n_s_per_m");
    s.table_friction = p.real("table_friction");
    s.substeps = static_cast<int>(p.integer("substeps"));
    body_.configure(s, 1.0 / context.rate_hz);
    hands_ = context.devices.size();
  }

  Outcome activate(std::span<const GroupHand> hands) override {
    if (hands.size() != hands_) return Outcome::failure("the group has another number of devices than configured");
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const GroupHand& h : hands) centre += h.pose.position;
    centre /= static_cast<double>(hands.size());
    Eigen::Vector3d along = hands[1].pose.position - hands[0].pose.position;
    along.z() = 0.0;
    const double yaw = along.norm() > 1e-9 ? std::atan2(along.y(), along.x()) : 0.0;
    Pose pose;
    pose.position = centre;
    pose.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
    for (std::size_t k = 0; k < hands.size(); ++k)
      grasp_[k] = pose.orientation.conjugate() * (hands[k].pose.position - centre);
    body_.reset(pose, std::span<const Eigen::Vector3d>(grasp_.data(), hands.size()));
    publish();
    return Outcome::success();
  }

  Outcome update(const CycleTime&, std::span<const GroupHand> hands, std::span<Eigen::Vector3d> handle_force) override {
    if (hands.size() != hands_ || handle_force.size() != hands_)
      return Outcome::failure("the group has another number of devices than configured");
    for (std::size_t k = 0; k < hands_; ++k) {
      if (hands[k].running) {
        position_[k] = hands[k].pose.position;
        velocity_[k] = hands[k].twist.linear;
      } else {  // a stopped device lets go: its coupling pulls on nothing
        position_[k] = body_.grasp_point(k);
        velocity_[k] = body_.velocity() + body_.angular_velocity().cross(position_[k] - body_.position());
      }
    }
    body_.step(std::span<const Eigen::Vector3d>(position_.data(), hands_),
               std::span<const Eigen::Vector3d>(velocity_.data(), hands_), handle_force);
    publish();
    return Outcome::success();
  }

  void deactivate() override {}

  RuntimeReply handle_request(std::string_view name, const std::vector<double>&) override {
    if (name != "state") return GroupModel::handle_request(name, {});
    ObjectState s;
    const bool fresh = latest_.take(s);
    if (fresh) kept_ = s;
    const ObjectState& k = kept_;
    return {true,
            "position, orientation (w x y z), internal force, table force",
            {k.position.x(), k.position.y(), k.position.z(), k.orientation.w(), k.orientation.x(), k.orientation.y(),
             k.orientation.z(), k.internal_force_n, k.table_force_n}};
  }

 private:
  void publish() noexcept {
    ObjectState s;
    s.position = body_.position();
    s.orientation = body_.orientation();
    s.internal_force_n = body_.internal_force_n();
    s.table_force_n = body_.table_force().z();
    latest_.publish(s);
  }

  SharedBody body_;
  std::size_t hands_ = 0;
  std::array<Eigen::Vector3d, SharedBody::kMaxHands> grasp_{}, position_{}, velocity_{};
  realtime::LatestValue<ObjectState> latest_;  // loop -> request thread
  ObjectState kept_;                           // request thread: the last taken
};

}  // namespace
}  // namespace hapticd::group_models

HAPTICD_PLUGIN_LIBRARY(hapticd::describe_plugin<hapticd::group_models::SharedObjectModel>(
    "shared_object", "1.0",
    "bimanual coupling: the group's hands hold one virtual rigid box (mass, inertia, gravity, "
    "a table)"))
