#include "hapticd/scene/proxy.hpp"

#include <algorithm>
#include <cmath>

namespace hapticd::scene {
namespace {

constexpr double kSkin = 1e-7;              // a sweep stops this short of a surface [m]
constexpr double kContactTolerance = 2e-6;  // within this of a surface the proxy touches it [m]
constexpr double kForceTolerance = 1e-5;    // within this, a contact shares the force [m]
constexpr int kSweepSteps = 32;
constexpr int kProjectionSweeps = 256;

}  // namespace

void GodObject::configure(const ProxySettings& settings, const Scene& scene) {
  settings_ = settings;
  scene_ = &scene;
  ignored_.assign(scene.objects.size(), 0);
  bounds_.resize(scene.objects.size());
  for (std::size_t i = 0; i < scene.objects.size(); ++i) bounds_[i] = bounding_radius(scene.objects[i].shape);
  state_ = ProxyState{};
}

double GodObject::stiffness_of(const Material& m) const noexcept {
  return std::min(m.stiffness_n_per_m, settings_.max_stiffness_n_per_m);
}

void GodObject::reset(const Eigen::Vector3d& goal) noexcept {
  state_ = ProxyState{};
  state_.proxy = goal;
  sliding_ = false;
  for (std::size_t i = 0; i < ignored_.size(); ++i)
    ignored_[i] = closest_in_world(scene_->objects[i], goal).distance < settings_.radius_m ? 1 : 0;
}

int GodObject::gather(const Eigen::Vector3d& x, double tolerance, Planes& planes) const noexcept {
  int count = 0;
  const double r = settings_.radius_m;
  for (std::size_t i = 0; i < scene_->objects.size() && count < kMaxContacts; ++i) {
    if (skipped(i)) continue;
    const SceneObject& o = scene_->objects[i];
    if ((x - o.pose.translation()).norm() - bounds_[i] - r > tolerance) continue;
    const SurfacePoint s = closest_in_world(o, x);
    if (s.distance - r > tolerance) continue;
    planes[static_cast<std::size_t>(count++)] =
        Plane{s.normal, s.normal.dot(s.point) + r + kSkin, static_cast<int>(i), s};
  }
  return count;
}

// Hildreth's method: the point nearest `goal` that satisfies every plane (cyclic projections with their
// multipliers kept non-negative: converges to the exact solution, also with dependent planes).
Eigen::Vector3d GodObject::project(const Eigen::Vector3d& goal, const Planes& planes, int count) noexcept {
  std::array<double, kMaxContacts> lambda{};
  Eigen::Vector3d x = goal;
  for (int sweep = 0; sweep < kProjectionSweeps && count > 0; ++sweep) {
    double largest = 0.0;
    for (int j = 0; j < count; ++j) {
      const Plane& p = planes[static_cast<std::size_t>(j)];
      const double old = lambda[static_cast<std::size_t>(j)];
      const double next = std::max(0.0, old + (p.offset - p.normal.dot(x)));
      x += (next - old) * p.normal;
      lambda[static_cast<std::size_t>(j)] = next;
      largest = std::max(largest, std::abs(next - old));
    }
    if (largest < 1e-12) break;
  }
  return x;
}

// Conservative advancement: each step goes as far as the plane that separates the proxy from the nearest
// object on its way (for a convex shape the tangent plane at the closest point holds the whole shape behind
// it), so the swept sphere never enters an object.
Eigen::Vector3d GodObject::sweep(const Eigen::Vector3d& from, const Eigen::Vector3d& to, bool& hit) const noexcept {
  hit = false;
  Eigen::Vector3d x = from;
  const double r = settings_.radius_m;
  for (int k = 0; k < kSweepSteps; ++k) {
    const Eigen::Vector3d delta = to - x;
    const double length = delta.norm();
    if (length < 1e-12) return to;
    const Eigen::Vector3d u = delta / length;
    double step = length;
    bool limited = false;
    for (std::size_t i = 0; i < scene_->objects.size(); ++i) {
      if (skipped(i)) continue;
      const SceneObject& o = scene_->objects[i];
      if ((x - o.pose.translation()).norm() - bounds_[i] - r > step) continue;
      const SurfacePoint s = closest_in_world(o, x);
      const double approach = -s.normal.dot(u);
      if (approach <= 1e-7) continue;
      const double t = std::max(0.0, (s.distance - r - kSkin) / approach);
      if (t < step) {
        step = t;
        limited = true;
      }
    }
    x += step * u;
    if (!limited) return to;
    if (step <= 1e-10) break;
  }
  hit = true;
  return x;
}

Eigen::Vector3d GodObject::solve(const Eigen::Vector3d& start, const Eigen::Vector3d& goal) const noexcept {
  Eigen::Vector3d x = start;
  Planes planes;
  for (int i = 0; i < settings_.max_iterations; ++i) {
    const int count = gather(x, kContactTolerance, planes);
    const Eigen::Vector3d target = project(goal, planes, count);
    bool hit = false;
    x = sweep(x, target, hit);
    if (!hit) break;
  }
  return x;
}

const ProxyState& GodObject::update(const Eigen::Vector3d& goal, const Eigen::Vector3d& goal_velocity) noexcept {
  const double r = settings_.radius_m;
  for (std::size_t i = 0; i < ignored_.size(); ++i)
    if (ignored_[i] != 0 && closest_in_world(scene_->objects[i], goal).distance > r) ignored_[i] = 0;

  // 1. Where the proxy would go without friction.
  const Eigen::Vector3d previous = state_.proxy;
  const Eigen::Vector3d free = solve(previous, goal);
  Planes planes;
  int count = gather(free, kForceTolerance, planes);

  // The contact that carries the most of the spring: its material rules the spring and the friction.
  auto dominant = [&](const Eigen::Vector3d& proxy) {
    int best = -1;
    double most = -1.0;
    for (int j = 0; j < count; ++j) {
      const double share = (proxy - goal).dot(planes[static_cast<std::size_t>(j)].normal);
      if (share > most) {
        most = share;
        best = j;
      }
    }
    return best;
  };

  // 2. Friction: stick within the static cone, slide against the dynamic one.
  Eigen::Vector3d proxy = free;
  state_.sliding = false;
  const Eigen::Vector3d depth_vector = free - goal;
  const double depth = depth_vector.norm();
  const int main = dominant(free);
  if (main >= 0 && depth > 1e-12) {
    const Material& m =
        scene_->objects[static_cast<std::size_t>(planes[static_cast<std::size_t>(main)].object)].material;
    if (m.static_friction > 0.0 || m.dynamic_friction > 0.0) {
      const Eigen::Vector3d n = depth_vector / depth;
      Eigen::Vector3d offset = previous - free;
      offset -= offset.dot(n) * n;
      const double held = offset.norm();
      const double cone = (sliding_ ? m.dynamic_friction : m.static_friction) * depth;
      Eigen::Vector3d shift = offset;
      if (held > cone * (1.0 + 1e-9) + 1e-12) {  // (a hand at rest after sliding sits on the cone: stuck)
        shift = offset * (m.dynamic_friction * depth / held);
        state_.sliding = true;
      }
      if (shift.squaredNorm() > 0.0) {
        proxy = solve(previous, goal + shift);
        count = gather(proxy, kForceTolerance, planes);
      }
    }
  }
  sliding_ = state_.sliding;

  // 3. The force on the device's point: the spring (the main contact's stiffness), shared among the contacts
  // by how much of it each one's normal carries, plus each contact's damping and texture along its normal.
  const int rule = dominant(proxy);
  if (rule >= 0) {
    const SceneObject& o = scene_->objects[static_cast<std::size_t>(planes[static_cast<std::size_t>(rule)].object)];
    last_stiffness_ = stiffness_of(o.material);
  }
  const Eigen::Vector3d spring = last_stiffness_ * (proxy - goal);
  double shares = 0.0;
  for (int j = 0; j < count; ++j) shares += std::max(0.0, spring.dot(planes[static_cast<std::size_t>(j)].normal));
  Eigen::Vector3d force = count > 0 ? Eigen::Vector3d::Zero() : spring;
  state_.contact_count = 0;
  for (int j = 0; j < count; ++j) {
    const Plane& p = planes[static_cast<std::size_t>(j)];
    const SceneObject& o = scene_->objects[static_cast<std::size_t>(p.object)];
    const double k = stiffness_of(o.material);
    const double scale = o.material.stiffness_n_per_m > 0.0 ? k / o.material.stiffness_n_per_m : 0.0;
    const double share = shares > 0.0 ? std::max(0.0, spring.dot(p.normal)) / shares : (j == 0 ? 1.0 : 0.0);
    Eigen::Vector3d own = share * spring;
    const double into = goal_velocity.dot(p.normal);
    if (into < 0.0) own -= o.material.damping_n_s_per_m * scale * into * p.normal;
    const Eigen::Vector3d local = o.pose.inverse(Eigen::Isometry) * p.surface.point;
    own += k * texture_height(o.material, local) * p.normal;
    const double normal_part = own.dot(p.normal);
    if (normal_part < 0.0) own -= normal_part * p.normal;  // a surface pushes, never pulls
    ProxyContact& c = state_.contacts[static_cast<std::size_t>(state_.contact_count++)];
    c.object = p.object;
    c.point = p.surface.point;
    c.normal = p.normal;
    c.force = own;
    force += own;
  }
  state_.proxy = proxy;
  state_.force = force;
  return state_;
}

}  // namespace hapticd::scene
