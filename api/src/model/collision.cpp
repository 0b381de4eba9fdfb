#include "hapticd/model/collision.hpp"

#include <algorithm>

#include "hapticd/model/model_data.hpp"
#include "hapticd/model/robot_model.hpp"

namespace hapticd::model {

SegmentPair closest_points(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& q0,
                           const Eigen::Vector3d& q1) noexcept {
  constexpr double kTiny = 1e-18;
  const Eigen::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0.0, t = 0.0;
  if (a <= kTiny && e <= kTiny) {  // two points
  } else if (a <= kTiny) {         // a point and a segment
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= kTiny) {  // a segment and a point
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denominator = a * e - b * b;
      // Not parallel: the closest point of the lines, clamped to the first segment; parallel: any s, take 0.
      s = denominator > kTiny * a * e ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  SegmentPair out;
  out.on_p = p0 + s * d1;
  out.on_q = q0 + t * d2;
  out.distance = (out.on_p - out.on_q).norm();
  return out;
}

Clearance capsule_clearance(const PlacedCapsules& first, int i, const PlacedCapsules& second, int j) noexcept {
  const auto ii = static_cast<std::size_t>(i), jj = static_cast<std::size_t>(j);
  const SegmentPair s = closest_points(first.a[ii], first.b[ii], second.a[jj], second.b[jj]);
  Clearance c;
  c.distance = s.distance - first.radius[ii] - second.radius[jj];
  c.capsule_first = i;
  c.capsule_second = j;
  // The surface points along the line between the segments' closest points (any direction when they meet).
  const Eigen::Vector3d along =
      s.distance > 1e-12 ? Eigen::Vector3d((s.on_q - s.on_p) / s.distance) : Eigen::Vector3d::UnitX();
  c.point_first = s.on_p + first.radius[ii] * along;
  c.point_second = s.on_q - second.radius[jj] * along;
  c.normal = -along;
  return c;
}

Clearance nearest(const PlacedCapsules& first, const PlacedCapsules& second) noexcept {
  Clearance best;
  for (int i = 0; i < first.count; ++i) {
    for (int j = 0; j < second.count; ++j) {
      const Clearance c = capsule_clearance(first, i, second, j);
      if (c.distance < best.distance) best = c;
    }
  }
  return best;
}

std::vector<Capsule> skeleton_capsules(const RobotModel& model, double radius) {
  std::vector<Capsule> out;
  const auto add = [&](int body, const Eigen::Vector3d& to) {
    if (to.norm() < 1e-6) return;  // a frame at the joint: nothing to cover
    for (const Capsule& c : out)
      if (c.body == body && (c.b - to).norm() < 1e-6) return;  // the next joint sits at a named frame
    const std::string& link = body < 0 ? model.frames().front().name : model.body(body).link_name;
    out.push_back(Capsule{link, body, Eigen::Vector3d::Zero(), to, radius});
  };
  for (int i = -1; i < model.dof(); ++i) {
    if (i + 1 < model.dof()) add(i, model.body(i + 1).placement.translation());
    for (const Frame& f : model.frames())
      if (f.body == i && i >= 0) add(i, f.placement.translation());
  }
  // Every body gets at least its joint: a sphere there when nothing else covers it.
  for (int i = 0; i < model.dof(); ++i) {
    bool covered = false;
    for (const Capsule& c : out) covered = covered || c.body == i;
    if (!covered)
      out.push_back(Capsule{model.body(i).link_name, i, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), radius});
  }
  return out;
}

void clearance_gradient(const RobotModel& model, const ModelData& data, int body, const Eigen::Vector3d& point,
                        const Eigen::Vector3d& normal, JointVector& gradient) noexcept {
  gradient.setZero(model.dof());
  for (int j = 0; j <= body; ++j) {  // the joints between the base and the body move the point
    const Motion& s = data.motion_subspace[static_cast<std::size_t>(j)];
    gradient[j] = normal.dot(s.linear + s.angular.cross(point));  // v_O + w x p along the normal
  }
}

void place_capsules(const RobotModel& model, const ModelData& data, PlacedCapsules& out) noexcept {
  const auto& capsules = model.collision();
  out.count = std::min<int>(static_cast<int>(capsules.size()), PlacedCapsules::kMax);
  for (int k = 0; k < out.count; ++k) {
    const Capsule& c = capsules[static_cast<std::size_t>(k)];
    const auto kk = static_cast<std::size_t>(k);
    if (c.body < 0) {
      out.a[kk] = c.a;
      out.b[kk] = c.b;
    } else {
      const auto body = static_cast<std::size_t>(c.body);
      out.a[kk] = data.position[body] + data.rotation[body] * c.a;
      out.b[kk] = data.position[body] + data.rotation[body] * c.b;
    }
    out.radius[kk] = c.radius;
  }
}

}  // namespace hapticd::model
