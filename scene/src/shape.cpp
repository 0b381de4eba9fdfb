#include "hapticd/scene/shape.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hapticd/scene/mesh.hpp"

namespace hapticd::scene {
namespace {

constexpr double kTiny = 1e-12;

SurfacePoint plane(const Eigen::Vector3d& p) {
  return {Eigen::Vector3d(p.x(), p.y(), 0.0), Eigen::Vector3d::UnitZ(), p.z()};
}

// About a centre point: the sphere's surface, and the capsule's about the nearest point of its axis segment.
SurfacePoint round(const Eigen::Vector3d& p, const Eigen::Vector3d& centre, double radius,
                   const Eigen::Vector3d& fallback) {
  const Eigen::Vector3d v = p - centre;
  const double n = v.norm();
  const Eigen::Vector3d normal = n > kTiny ? Eigen::Vector3d(v / n) : fallback;
  return {centre + radius * normal, normal, n - radius};
}

SurfacePoint box(const Eigen::Vector3d& p, const Eigen::Vector3d& e) {
  const Eigen::Vector3d q = p.cwiseAbs() - e;
  if (q.maxCoeff() > 0.0) {
    const Eigen::Vector3d c = p.cwiseMax(-e).cwiseMin(e);
    const Eigen::Vector3d v = p - c;
    const double d = v.norm();
    if (d > kTiny) return {c, v / d, d};
  }
  // Inside (or on a face): the face nearest to the point.
  int axis = 0;
  q.maxCoeff(&axis);
  Eigen::Vector3d c = p;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  const double side = p[axis] >= 0.0 ? 1.0 : -1.0;
  c[axis] = side * e[axis];
  normal[axis] = side;
  return {c, normal, q[axis]};
}

SurfacePoint cylinder(const Eigen::Vector3d& p, double radius, double half_length) {
  const double r = std::hypot(p.x(), p.y());
  const Eigen::Vector3d radial = r > kTiny ? Eigen::Vector3d(p.x() / r, p.y() / r, 0.0) : Eigen::Vector3d::UnitX();
  const double dr = r - radius;
  const double dz = std::abs(p.z()) - half_length;
  const double side = p.z() >= 0.0 ? 1.0 : -1.0;
  if (dr > 0.0 || dz > 0.0) {
    const Eigen::Vector3d c =
        std::min(r, radius) * radial + Eigen::Vector3d(0, 0, std::clamp(p.z(), -half_length, half_length));
    const Eigen::Vector3d v = p - c;
    const double d = v.norm();
    if (d > kTiny) return {c, v / d, d};
  }
  if (dr > dz) return {radius * radial + Eigen::Vector3d(0, 0, p.z()), radial, dr};
  return {Eigen::Vector3d(p.x(), p.y(), side * half_length), Eigen::Vector3d(0, 0, side), dz};
}

}  // namespace

SurfacePoint closest_point(const Shape& shape, const Eigen::Vector3d& p) noexcept {
  switch (shape.kind) {
    case ShapeKind::plane:
      return plane(p);
    case ShapeKind::sphere:
      return round(p, Eigen::Vector3d::Zero(), shape.radius, Eigen::Vector3d::UnitZ());
    case ShapeKind::box:
      return box(p, shape.half_extents);
    case ShapeKind::capsule: {
      const double s = std::clamp(p.z(), -shape.half_length, shape.half_length);
      return round(p, Eigen::Vector3d(0, 0, s), shape.radius, Eigen::Vector3d::UnitX());
    }
    case ShapeKind::cylinder:
      return cylinder(p, shape.radius, shape.half_length);
    case ShapeKind::mesh: {
      MeshShape::Near near{};
      if (!shape.mesh || !shape.mesh->nearest(p, 1.0, near)) return {p, Eigen::Vector3d::UnitZ(), 1e9};
      const Eigen::Vector3d v = p - near.closest.point;
      const double d = v.norm();
      return {near.closest.point, d > 1e-12 ? Eigen::Vector3d(v / d) : shape.mesh->face_normal(near.triangle), d};
    }
  }
  return plane(p);
}

double bounding_radius(const Shape& shape) noexcept {
  switch (shape.kind) {
    case ShapeKind::plane:
      return std::numeric_limits<double>::infinity();
    case ShapeKind::sphere:
      return shape.radius;
    case ShapeKind::box:
      return shape.half_extents.norm();
    case ShapeKind::capsule:
      return shape.radius + shape.half_length;
    case ShapeKind::cylinder:
      return std::hypot(shape.radius, shape.half_length);
    case ShapeKind::mesh:
      return shape.mesh ? shape.mesh->bounding_radius() : 0.0;
  }
  return std::numeric_limits<double>::infinity();
}

const char* kind_name(ShapeKind kind) noexcept {
  switch (kind) {
    case ShapeKind::plane:
      return "plane";
    case ShapeKind::sphere:
      return "sphere";
    case ShapeKind::box:
      return "box";
    case ShapeKind::capsule:
      return "capsule";
    case ShapeKind::cylinder:
      return "cylinder";
    case ShapeKind::mesh:
      return "mesh";
  }
  return "?";
}

}  // namespace hapticd::scene
