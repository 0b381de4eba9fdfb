#include "hapticd/scene/proxy.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "hapticd/scene/mesh.hpp"

namespace hapticd::scene {
namespace {

constexpr double kSkin = 1e-7;              // a sweep stops this short of a surface [m]
constexpr double kContactTolerance = 2e-6;  // within this of a surface the proxy touches it [m]
constexpr double kForceTolerance = 1e-6;    // within this, a contact shares the force [m] (a mesh's neighbours just
                                            // beyond the contact would tilt it by their rounded edges)
constexpr int kSweepSteps = 32;
constexpr double kMeshReach = 1e-4;  // a sweep step asks a mesh about at most this far ahead [m]

}  // namespace

void GodObject::configure(const ProxySettings& settings, const Scene& scene) {
  settings_ = settings;
  scene_ = &scene;
  ignored_.reserve(std::max(kMaxSceneObjects, scene.objects.size()));  // rebind() resizes within these
  bounds_.reserve(std::max(kMaxSceneObjects, scene.objects.size()));
  ignored_.assign(scene.objects.size(), 0);
  bounds_.resize(scene.objects.size());
  for (std::size_t i = 0; i < scene.objects.size(); ++i) bounds_[i] = bounding_radius(scene.objects[i].shape);
  state_ = ProxyState{};
  free_ = state_.proxy;
}

void GodObject::rebind(const Scene& scene) noexcept {
  // The objects the proxy was leaving out, by their ids (a handful at most: those it started or was made in).
  std::array<std::uint64_t, 16> left_out{};
  std::size_t n = 0;
  for (std::size_t i = 0; i < ignored_.size() && n < left_out.size(); ++i)
    if (ignored_[i] != 0 && scene_->objects[i].uid != 0) left_out[n++] = scene_->objects[i].uid;
  scene_ = &scene;
  const std::size_t count = std::min(scene.objects.size(), ignored_.capacity());  // no allocation
  ignored_.resize(count);
  bounds_.resize(count);
  const double r = settings_.radius_m;
  for (std::size_t i = 0; i < count; ++i) {
    const SceneObject& o = scene.objects[i];
    bounds_[i] = bounding_radius(o.shape);
    bool skip = o.uid != 0 && std::find(left_out.begin(), left_out.begin() + static_cast<std::ptrdiff_t>(n), o.uid) !=
                                  left_out.begin() + static_cast<std::ptrdiff_t>(n);
    // Made around the proxy: more than half its radius into it (an object the proxy rests on is a radius away).
    if (!skip && (state_.proxy - o.pose.translation()).norm() - bounds_[i] < r)
      skip = closest_in_world(o, state_.proxy).distance < 0.5 * r;
    ignored_[i] = skip ? 1 : 0;
  }
  state_.contact_count = 0;  // the contacts named the old scene's objects; the next update finds them again
  free_ = state_.proxy;
}

double GodObject::stiffness_of(const Material& m) const noexcept {
  return std::min(m.stiffness_n_per_m, settings_.max_stiffness_n_per_m);
}

void GodObject::reset(const Eigen::Vector3d& goal) noexcept {
  state_ = ProxyState{};
  state_.proxy = goal;
  sliding_ = false;
  free_ = goal;
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
    if (o.shape.kind == ShapeKind::mesh) {
      gather_mesh(i, x, tolerance, planes, count);
      continue;
    }
    const SurfacePoint s = closest_in_world(o, x);
    if (s.distance - r > tolerance) continue;
    planes[static_cast<std::size_t>(count++)] =
        Plane{s.normal, s.normal.dot(s.point) + r + kSkin, static_cast<int>(i), s, s.normal};
  }
  return count;
}

// A mesh's contact planes: one per triangle within reach, its normal the direction from the triangle's closest
// point to the proxy's centre (the sphere against the triangle: flat on its face, round at its edges and corners);
// planes that repeat one already taken (neighbours sharing the closest edge or vertex) are left out.
void GodObject::gather_mesh(std::size_t object, const Eigen::Vector3d& x, double tolerance, Planes& planes,
                            int& count) const noexcept {
  const SceneObject& o = scene_->objects[object];
  // Contacts on an edge or a corner towards a coplanar or concave neighbour are kept aside: they count only when
  // no face (or convex edge) of the mesh holds the proxy - a proxy resting on a grid's vertex, say.
  struct Context {
    const GodObject* self;
    const SceneObject* o;
    const MeshShape* mesh;
    Eigen::Vector3d local;
    Planes* planes;
    int* count;
    int object;
    int own;
    Planes aside;
    int aside_count;
  } c{this, &o, o.shape.mesh.get(), o.pose.inverse(Eigen::Isometry) * x, &planes, &count, static_cast<int>(object), 0,
      {},   0};
  o.shape.mesh->for_each_near(
      c.local, settings_.radius_m + tolerance,
      [](void* p, const MeshShape::Near& near) {
        auto* c = static_cast<Context*>(p);
        const Eigen::Vector3d v = c->local - near.closest.point;
        const double d = v.norm();
        const Eigen::Vector3d local_normal = d > 1e-12 ? Eigen::Vector3d(v / d) : c->mesh->face_normal(near.triangle);
        const Eigen::Vector3d normal = c->o->pose.linear() * local_normal;
        const Eigen::Vector3d point = c->o->pose * near.closest.point;
        const double offset = normal.dot(point) + c->self->settings_.radius_m + kSkin;
        const bool own = c->mesh->own_contact(near.triangle, near.closest.barycentric);
        Planes& into = own ? *c->planes : c->aside;
        int& n = own ? *c->count : c->aside_count;
        if (n >= kMaxContacts) return;
        for (int j = 0; j < n; ++j) {
          const Plane& q = into[static_cast<std::size_t>(j)];
          if (q.object == c->object && q.normal.dot(normal) > 1.0 - 1e-12 && std::abs(q.offset - offset) < 1e-12)
            return;
        }
        // Force shading: the vertex normals at the closest point, where the proxy meets the face from its front.
        Eigen::Vector3d shaded = normal;
        const Eigen::Vector3d s = c->mesh->shaded_normal(near.triangle, near.closest.barycentric);
        if (c->self->settings_.force_shading && local_normal.dot(c->mesh->face_normal(near.triangle)) > 0.0 &&
            s.dot(local_normal) > 0.0)
          shaded = c->o->pose.linear() * s;
        into[static_cast<std::size_t>(n++)] = Plane{normal, offset, c->object, SurfacePoint{point, normal, d}, shaded};
        if (own) ++c->own;
      },
      &c);
  if (c.own > 0) return;
  for (int j = 0; j < c.aside_count && count < kMaxContacts; ++j)
    planes[static_cast<std::size_t>(count++)] = c.aside[static_cast<std::size_t>(j)];
}

double GodObject::mesh_step(std::size_t object, const Eigen::Vector3d& x, const Eigen::Vector3d& u,
                            double step) const noexcept {
  // At most kMeshReach ahead: a query's triangles grow with its reach (a disc of about sqrt(2 r reach) on a surface
  // the proxy touches: at 2 mm, 35 000 of a 1.3 million-triangle pebble's), and a longer way is taken in more steps.
  step = std::min(step, kMeshReach);
  const SceneObject& o = scene_->objects[object];
  struct Context {
    Eigen::Vector3d local, u;
    double r, step;
  } c{o.pose.inverse(Eigen::Isometry) * x, o.pose.linear().transpose() * u, settings_.radius_m, step};
  o.shape.mesh->for_each_ahead(
      c.local, c.r + step + kSkin, c.u,
      [](void* p, const MeshShape::Near& near) {
        auto* c = static_cast<Context*>(p);
        const Eigen::Vector3d v = c->local - near.closest.point;
        const double d = v.norm();
        if (d < 1e-12) return;
        const double approach = -(v / d).dot(c->u);
        if (approach <= 1e-7) return;
        c->step = std::min(c->step, std::max(0.0, (d - c->r - kSkin) / approach));
      },
      &c);
  return c.step;
}

// The point nearest `goal` that satisfies every plane: an active-set method on the normal equations. In three
// dimensions at most three independent planes are active (a corner); a plane that depends on the active ones
// (its normal in their span: a duplicate, or a fourth at a corner) is not added. Exact, also for planes a few
// degrees apart (a mesh's neighbouring facets), where cyclic projections would need thousands of sweeps.
Eigen::Vector3d GodObject::project(const Eigen::Vector3d& goal, const Planes& planes, int count) noexcept {
  std::array<int, 3> active{};
  int n = 0;
  Eigen::Vector3d x = goal;
  Eigen::Vector3d lambda = Eigen::Vector3d::Zero();
  // x = goal + sum lambda_i normal_i with normal_i . x = offset_i for the active planes.
  auto solve = [&]() {
    Eigen::Matrix3d gram = Eigen::Matrix3d::Identity();
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    for (int a = 0; a < n; ++a) {
      const Plane& pa = planes[static_cast<std::size_t>(active[static_cast<std::size_t>(a)])];
      rhs[a] = pa.offset - pa.normal.dot(goal);
      for (int b = 0; b < n; ++b)
        gram(a, b) = pa.normal.dot(planes[static_cast<std::size_t>(active[static_cast<std::size_t>(b)])].normal);
    }
    lambda = gram.inverse() * rhs;  // the unused rows and columns are the identity's
    x = goal;
    for (int a = n; a < 3; ++a) lambda[a] = 0.0;
    for (int a = 0; a < n; ++a)
      x += lambda[a] * planes[static_cast<std::size_t>(active[static_cast<std::size_t>(a)])].normal;
  };
  auto independent = [&](const Eigen::Vector3d& normal) {
    if (n == 0) return true;
    const Eigen::Vector3d& a = planes[static_cast<std::size_t>(active[0])].normal;
    if (n == 1) return a.cross(normal).squaredNorm() > 1e-14;
    const Eigen::Vector3d& b = planes[static_cast<std::size_t>(active[1])].normal;
    return n == 2 && std::abs(a.cross(b).normalized().dot(normal)) > 1e-7;
  };
  for (int iteration = 0; iteration < 4 * kMaxContacts; ++iteration) {
    // A multiplier below zero: that plane pulls; it leaves the active set.
    int worst_active = -1;
    for (int a = 0; a < n; ++a)
      if (lambda[a] < -1e-15 && (worst_active < 0 || lambda[a] < lambda[worst_active])) worst_active = a;
    if (worst_active >= 0) {
      for (int a = worst_active; a + 1 < n; ++a)
        active[static_cast<std::size_t>(a)] = active[static_cast<std::size_t>(a + 1)];
      --n;
      solve();
      continue;
    }
    // The plane x violates most joins it, if it is independent of the active ones.
    int worst = -1;
    double most = -1e-13;
    for (int j = 0; j < count; ++j) {
      const Plane& p = planes[static_cast<std::size_t>(j)];
      const double v = p.normal.dot(x) - p.offset;
      if (v < most && independent(p.normal)) {
        most = v;
        worst = j;
      }
    }
    if (worst < 0) break;
    if (n == 3) break;  // (cannot happen: three independent planes fix x)
    active[static_cast<std::size_t>(n++)] = worst;
    solve();
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
      if (o.shape.kind == ShapeKind::mesh) {
        const double t = mesh_step(i, x, u, step);
        if (t < step) {
          step = t;
          limited = true;
        }
        continue;
      }
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

Eigen::Vector3d GodObject::solve(const Eigen::Vector3d& start, const Eigen::Vector3d& goal,
                                 int& iterations) const noexcept {
  Eigen::Vector3d x = start;
  Planes planes;
  for (int i = 0; i < settings_.max_iterations; ++i) {
    ++iterations;
    const int count = gather(x, kContactTolerance, planes);
    const Eigen::Vector3d target = project(goal, planes, count);
    bool hit = false;
    const Eigen::Vector3d from = x;
    x = sweep(x, target, hit);
    if (hit) continue;  // stopped at a new contact: again from there with its plane
    // Reached the target: the goal itself, or a point the contact planes hold. The planes are tangents taken where
    // the proxy was; where it is now they may have turned (a round surface, a mesh's rounded edge) or held it in
    // the air off a convex edge: again from here until it no longer moves.
    if (count == 0 || (target - goal).squaredNorm() < 1e-24 || (x - from).squaredNorm() < 1e-14) break;
  }
  return x;
}

const ProxyState& GodObject::update(const Eigen::Vector3d& goal, const Eigen::Vector3d& goal_velocity) noexcept {
  const double r = settings_.radius_m;
  for (std::size_t i = 0; i < ignored_.size(); ++i)
    if (ignored_[i] != 0 && closest_in_world(scene_->objects[i], goal).distance > r) ignored_[i] = 0;

  // 0. An object that moved into the proxy pushes it out (and so the hand, through the spring); the frictionless
  // point too, where friction holds the proxy apart from it (else it goes with the proxy).
  const bool apart = (free_ - state_.proxy).squaredNorm() > 0.0;
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t i = 0; i < scene_->objects.size(); ++i) {
      if (skipped(i)) continue;
      const SceneObject& o = scene_->objects[i];
      if ((state_.proxy - o.pose.translation()).norm() - bounds_[i] - r > 0.0) continue;
      const SurfacePoint s = closest_in_world(o, state_.proxy);
      if (s.distance < r + kSkin) state_.proxy += (r + kSkin - s.distance) * s.normal;
      if (apart) {
        const SurfacePoint f = closest_in_world(o, free_);
        if (f.distance < r + kSkin) free_ += (r + kSkin - f.distance) * f.normal;
      }
    }
  if (!apart) free_ = state_.proxy;

  // 1. Where the proxy would go without friction.
  const Eigen::Vector3d previous = state_.proxy;
  state_.iterations = 0;
  const Eigen::Vector3d free = solve(free_, goal, state_.iterations);
  free_ = free;
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
        proxy = solve(previous, goal + shift, state_.iterations);
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
  Eigen::Vector3d spring = last_stiffness_ * (proxy - goal);
  // Force shading: the spring (its normal part and the friction across it) turned as the main contact's facet
  // normal turns into its shaded normal, so a tessellated curve feels smooth and its edges are not felt. (One
  // turn for the whole spring: turning each contact's share by its own normal would tilt it by the neighbours'
  // rounded edges.)
  if (rule >= 0) {
    const Plane& main_plane = planes[static_cast<std::size_t>(rule)];
    if (main_plane.shaded.dot(main_plane.normal) < 1.0 - 1e-15)
      spring = Eigen::Quaterniond::FromTwoVectors(main_plane.normal, main_plane.shaded) * spring;
  }
  double shares = 0.0;
  for (int j = 0; j < count; ++j) shares += std::max(0.0, spring.dot(planes[static_cast<std::size_t>(j)].shaded));
  Eigen::Vector3d force = count > 0 ? Eigen::Vector3d::Zero() : spring;
  state_.contact_count = 0;
  for (int j = 0; j < count; ++j) {
    const Plane& p = planes[static_cast<std::size_t>(j)];
    const SceneObject& o = scene_->objects[static_cast<std::size_t>(p.object)];
    const double k = stiffness_of(o.material);
    const double scale = o.material.stiffness_n_per_m > 0.0 ? k / o.material.stiffness_n_per_m : 0.0;
    const double share = shares > 0.0 ? std::max(0.0, spring.dot(p.shaded)) / shares : (j == 0 ? 1.0 : 0.0);
    Eigen::Vector3d own = share * spring;
    const double into = (goal_velocity - o.velocity).dot(p.shaded);
    if (into < 0.0) own -= o.material.damping_n_s_per_m * scale * into * p.shaded;
    const Eigen::Vector3d local = o.pose.inverse(Eigen::Isometry) * p.surface.point;
    own += k * texture_height(o.material, local) * p.shaded;
    const double normal_part = own.dot(p.shaded);
    if (normal_part < 0.0) own -= normal_part * p.shaded;  // a surface pushes, never pulls
    ProxyContact& c = state_.contacts[static_cast<std::size_t>(state_.contact_count++)];
    c.object = p.object;
    c.point = p.surface.point;
    c.normal = p.shaded;
    c.force = own;
    force += own;
  }
  state_.proxy = proxy;
  state_.force = force;
  return state_;
}

}  // namespace hapticd::scene
