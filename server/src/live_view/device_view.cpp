#include "live_view/device_view.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <numeric>

#include "hapticd/json_text.hpp"
#include "hapticd/model/collision.hpp"
#include "hapticd/model/kinematics.hpp"
#include "live_view/scene_json.hpp"
#include "safety/device_fault.hpp"
#include "session/state_flags.hpp"

namespace hapticd::server::live_view {

using namespace json_text;
using namespace scene_json;

namespace {

constexpr Rgba kLinkColour{0.62, 0.64, 0.68, 1.0};
constexpr Rgba kCapsuleColour{0.62, 0.51, 0.78, 0.25};  // violet: no world object's colour
constexpr Rgba kHandleColour{0.15, 0.45, 0.95, 1.0};
constexpr Rgba kTargetColour{0.2, 0.8, 0.3, 0.5};
constexpr Rgba kProxyColour{1.0, 0.6, 0.0, 0.9};
constexpr Rgba kOperatorColour{0.9, 0.15, 0.15, 1.0};
constexpr Rgba kRenderedColour{0.1, 0.7, 0.2, 1.0};
constexpr double kLinkDiameter = 0.02, kJointDiameter = 0.03, kHandleDiameter = 0.025, kMarkerDiameter = 0.015;

void append_wrench(std::string& out, const Eigen::Vector3d& force, const Eigen::Vector3d& torque) {
  out += "{\"force\":";
  append_vector3(out, force.x(), force.y(), force.z());
  out += ",\"torque\":";
  append_vector3(out, torque.x(), torque.y(), torque.z());
  out += '}';
}

void append_numbers(std::string& out, const JointVector& v, int n) {
  out += '[';
  for (int i = 0; i < n; ++i) {
    if (i > 0) out += ',';
    append_number(out, v[i]);
  }
  out += ']';
}

void append_transform(std::string& out, bool first, std::uint64_t time_ns, const std::string& child,
                      const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  if (!first) out += ',';
  out += "{\"timestamp\":";
  append_time(out, time_ns);
  out += ",\"parent_frame_id\":\"world\",\"child_frame_id\":";
  append_string(out, child);
  out += ",\"translation\":";
  append_vector3(out, p.x(), p.y(), p.z());
  out += ",\"rotation\":";
  append_quaternion(out, q.x(), q.y(), q.z(), q.w());
  out += '}';
}

// An arrow from `tail` along `force`, its length scaled; none for a force below 10 mN.
void append_force_arrow(std::string& out, const Eigen::Vector3d& tail, const Eigen::Vector3d& force, double scale,
                        const Rgba& c) {
  out += ",\"arrows\":[";
  const double magnitude = force.norm();
  if (std::isfinite(magnitude) && magnitude >= 0.01) {
    const double length = magnitude * scale;
    const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitX(), force);
    out += "{\"pose\":";
    append_pose(out, tail, q);
    out += ",\"shaft_length\":";
    append_number(out, 0.8 * length);
    out += ",\"shaft_diameter\":";
    append_number(out, std::min(0.008, 0.1 * length + 0.002));
    out += ",\"head_length\":";
    append_number(out, 0.2 * length);
    out += ",\"head_diameter\":";
    append_number(out, std::min(0.016, 0.2 * length + 0.004));
    out += ",\"color\":";
    append_colour(out, c);
    out += '}';
  }
  out += ']';
}

}  // namespace

DeviceView::DeviceView(std::string device, const DeviceDescription& description,
                       std::shared_ptr<const model::RobotModel> model, std::vector<std::string> schemes,
                       DeviceViewSettings settings)
    : device_(std::move(device)), model_(std::move(model)), schemes_(std::move(schemes)), settings_(settings) {
  for (const JointDescription& j : description.joints) joint_names_.push_back(j.name);
  if (model_) {
    data_ = std::make_unique<model::ModelData>(*model_);
    // The models are unbranched chains: their frames ordered by the body they move with (the base's first) are
    // the chain from the base to the handle.
    skeleton_.resize(model_->frames().size());
    std::iota(skeleton_.begin(), skeleton_.end(), 0);
    std::stable_sort(skeleton_.begin(), skeleton_.end(),
                     [&](int a, int b) { return model_->frame(a).body < model_->frame(b).body; });
  }
}

void DeviceView::compute_posture(const DeviceSnapshot& s) {
  if (!model_ || posture_cycle_ == s.cycle) return;
  JointVector q = JointVector::Zero(model_->dof());
  for (int i = 0; i < model_->dof() && i < static_cast<int>(s.position.size()); ++i) q[i] = s.position[i];
  model::forward_kinematics(*model_, *data_, q, model::BodyInertias::skip);
  posture_cycle_ = s.cycle;
}

void DeviceView::frame_transforms(const DeviceSnapshot& s, std::uint64_t time_ns, std::string& out) {
  compute_posture(s);
  out = "{\"transforms\":[";
  bool first = true;
  if (model_) {
    for (int f = 0; f < static_cast<int>(model_->frames().size()); ++f) {
      const Eigen::Isometry3d pose = model::frame_pose(*model_, *data_, f);
      append_transform(out, first, time_ns, frame_of(model_->frame(f).name), pose.translation(),
                       Eigen::Quaterniond(pose.rotation()));
      first = false;
    }
  }
  append_transform(out, first, time_ns, device_ + "/handle_point", s.handle_pose.position, s.handle_pose.orientation);
  append_transform(out, false, time_ns, device_ + "/target", s.target_pose.position, s.target_pose.orientation);
  if (s.engine_has_proxy)
    append_transform(out, false, time_ns, device_ + "/proxy", s.engine_proxy_pose.position,
                     s.engine_proxy_pose.orientation);
  out += "]}";
}

void DeviceView::scene_update(const DeviceSnapshot& s, std::uint64_t time_ns, std::string& out) {
  compute_posture(s);
  out = "{\"deletions\":[],\"entities\":[";
  // The links: a skeleton through the chain's frames, a sphere at each joint; the collision capsules if any.
  begin_entity(out, true, time_ns, device_ + "/links");
  out += ",\"cylinders\":[";
  bool first = true;
  model::PlacedCapsules capsules;
  if (model_) {
    for (std::size_t k = 1; k < skeleton_.size(); ++k) {
      const Eigen::Vector3d a = model::frame_pose(*model_, *data_, skeleton_[k - 1]).translation();
      const Eigen::Vector3d b = model::frame_pose(*model_, *data_, skeleton_[k]).translation();
      if ((b - a).norm() < 1e-6) continue;
      append_cylinder(out, first, a, b, kLinkDiameter, kLinkColour);
      first = false;
    }
    model::place_capsules(*model_, *data_, capsules);
    for (int c = 0; c < capsules.count; ++c) {
      if ((capsules.b[c] - capsules.a[c]).norm() < 1e-6) continue;
      append_cylinder(out, first, capsules.a[c], capsules.b[c], 2.0 * capsules.radius[c], kCapsuleColour);
      first = false;
    }
  }
  out += "],\"spheres\":[";
  first = true;
  if (model_) {
    for (const int f : skeleton_) {
      if (model_->frame(f).body < 0) continue;
      append_sphere(out, first, model::frame_pose(*model_, *data_, f).translation(), kJointDiameter, kLinkColour);
      first = false;
    }
    for (int c = 0; c < capsules.count; ++c) {
      for (const Eigen::Vector3d* end : {&capsules.a[c], &capsules.b[c]}) {
        append_sphere(out, first, *end, 2.0 * capsules.radius[c], kCapsuleColour);
        first = false;
      }
    }
  }
  out += ']';
  empty_lists(out, {"arrows", "cubes", "lines", "triangles", "texts", "models"});
  end_entity(out);

  // The handle, the target and the engine's proxy (an empty entity while there is none: it replaces the last).
  begin_entity(out, false, time_ns, device_ + "/markers");
  out += ",\"spheres\":[";
  append_sphere(out, true, s.handle_pose.position, kHandleDiameter, kHandleColour);
  append_sphere(out, false, s.target_pose.position, kMarkerDiameter, kTargetColour);
  if (s.engine_has_proxy) append_sphere(out, false, s.engine_proxy_pose.position, kHandleDiameter, kProxyColour);
  out += ']';
  empty_lists(out, {"arrows", "cubes", "cylinders", "lines", "triangles", "texts", "models"});
  end_entity(out);

  // The wrenches' forces as arrows at the handle point.
  begin_entity(out, false, time_ns, device_ + "/operator_wrench");
  append_force_arrow(out, s.handle_pose.position, s.operator_wrench.force, settings_.force_scale_m_per_n,
                     kOperatorColour);
  empty_lists(out, {"cubes", "spheres", "cylinders", "lines", "triangles", "texts", "models"});
  end_entity(out);
  begin_entity(out, false, time_ns, device_ + "/rendered_wrench");
  append_force_arrow(out, s.handle_pose.position, s.environment_wrench.force, settings_.force_scale_m_per_n,
                     kRenderedColour);
  empty_lists(out, {"cubes", "spheres", "cylinders", "lines", "triangles", "texts", "models"});
  end_entity(out);
  out += "]}";
}

void DeviceView::device_state(const DeviceSnapshot& s, std::uint64_t time_ns, std::string& out) const {
  out = "{\"timestamp\":";
  append_time(out, time_ns);
  append_key(out, "device");
  append_string(out, device_);
  append_key(out, "cycle");
  append_integer(out, static_cast<std::int64_t>(s.cycle));
  append_key(out, "mode");
  append_string(out, kDeviceModeNames[static_cast<std::size_t>(device_mode(s))]);
  append_key(out, "flags");
  out += '[';
  const std::uint32_t flags = state_flags(s);
  bool first = true;
  for (std::size_t bit = 0; bit < kStateFlagNames.size(); ++bit) {
    if ((flags & (1u << bit)) == 0) continue;
    if (!first) out += ',';
    first = false;
    append_string(out, kStateFlagNames[bit]);
  }
  out += ']';
  append_key(out, "scheme");
  append_string(out, s.scheme >= 0 && static_cast<std::size_t>(s.scheme) < schemes_.size()
                         ? schemes_[static_cast<std::size_t>(s.scheme)]
                         : std::string());
  const int n =
      static_cast<int>(std::min<std::size_t>(joint_names_.size(), static_cast<std::size_t>(s.position.size())));
  append_key(out, "joints");
  out += "{\"name\":[";
  for (int i = 0; i < n; ++i) {
    if (i > 0) out += ',';
    append_string(out, joint_names_[static_cast<std::size_t>(i)]);
  }
  out += "],\"position\":";
  append_numbers(out, s.position, n);
  out += ",\"velocity\":";
  append_numbers(out, s.velocity, std::min(n, static_cast<int>(s.velocity.size())));
  out += ",\"torque\":";
  append_numbers(out, s.torque, std::min(n, static_cast<int>(s.torque.size())));
  out += '}';
  append_key(out, "handle");
  out += "{\"position\":";
  const Pose& h = s.handle_pose;
  append_vector3(out, h.position.x(), h.position.y(), h.position.z());
  out += ",\"orientation\":";
  append_quaternion(out, h.orientation.x(), h.orientation.y(), h.orientation.z(), h.orientation.w());
  out += ",\"linear_velocity\":";
  append_vector3(out, s.handle_twist.linear.x(), s.handle_twist.linear.y(), s.handle_twist.linear.z());
  out += ",\"angular_velocity\":";
  append_vector3(out, s.handle_twist.angular.x(), s.handle_twist.angular.y(), s.handle_twist.angular.z());
  out += '}';
  append_key(out, "target");
  append_pose(out, s.target_pose);
  append_key(out, "operator_wrench");
  append_wrench(out, s.operator_wrench.force, s.operator_wrench.torque);
  append_key(out, "rendered_wrench");
  append_wrench(out, s.environment_wrench.force, s.environment_wrench.torque);
  append_key(out, "engine");
  out += "{\"weight\":";
  append_number(out, s.engine_weight);
  out += ",\"stale\":";
  out += s.engine_stale ? "true" : "false";
  out += ",\"sequence\":";
  append_integer(out, static_cast<std::int64_t>(s.engine_sequence));
  out += ",\"proxy\":";
  if (s.engine_has_proxy)
    append_pose(out, s.engine_proxy_pose);
  else
    out += "null";
  out += ",\"wrench\":";
  if (s.engine_has_wrench)
    append_wrench(out, s.engine_wrench.force, s.engine_wrench.torque);
  else
    out += "null";
  out += '}';
  append_key(out, "safety");
  out += "{\"fault\":";
  append_string(out, to_string(s.fault));
  out += ",\"faults\":";
  append_integer(out, static_cast<std::int64_t>(s.faults));
  out += ",\"thermal_load\":";
  append_number(out, s.thermal_load);
  out += ",\"dissipated_j\":";
  append_number(out, s.dissipated_j);
  out += ",\"passivity_control\":";
  out += s.passivity_control ? "true" : "false";
  out += "}}";
}

}  // namespace hapticd::server::live_view
