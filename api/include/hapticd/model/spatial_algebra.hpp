#pragma once
// Spatial (6-D) vectors and inertias for the model toolbox, in the world frame at the world origin
// (Featherstone's "absolute coordinates"): all bodies share one frame, so propagating a quantity from a
// body to its parent is a plain sum, and composite inertias are sums. Motion vectors are [angular; linear]
// where linear is the velocity of the body-fixed point that is momentarily at the world origin.
#include <Eigen/Core>

namespace hapticd::model {

// Angular and linear parts of a motion vector (velocity, acceleration, joint motion subspace).
struct Motion {
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();

  Motion& operator+=(const Motion& o) noexcept {
    angular += o.angular;
    linear += o.linear;
    return *this;
  }
  [[nodiscard]] Motion operator*(double s) const noexcept { return {angular * s, linear * s}; }
  [[nodiscard]] Motion operator+(const Motion& o) const noexcept { return {angular + o.angular, linear + o.linear}; }
};

// Moment (about the world origin) and force parts of a force vector.
struct Force {
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  Eigen::Vector3d force = Eigen::Vector3d::Zero();

  Force& operator+=(const Force& o) noexcept {
    moment += o.moment;
    force += o.force;
    return *this;
  }
  [[nodiscard]] Force operator+(const Force& o) const noexcept { return {moment + o.moment, force + o.force}; }
};

// Power pairing m . f.
[[nodiscard]] inline double dot(const Motion& m, const Force& f) noexcept {
  return m.angular.dot(f.moment) + m.linear.dot(f.force);
}

// Motion cross product v x m (the derivative of a motion vector m fixed in a body moving with v).
[[nodiscard]] inline Motion cross(const Motion& v, const Motion& m) noexcept {
  return {v.angular.cross(m.angular), v.angular.cross(m.linear) + v.linear.cross(m.angular)};
}

// Force cross product v x* f.
[[nodiscard]] inline Force cross(const Motion& v, const Force& f) noexcept {
  return {v.angular.cross(f.moment) + v.linear.cross(f.force), v.angular.cross(f.force)};
}

// Rigid-body (or composite) inertia about the world origin, parametrised by mass m, first moment h = m c
// (c the centre of mass) and rotational inertia about the origin. Closed under addition.
struct SpatialInertia {
  double mass = 0.0;
  Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotational = Eigen::Matrix3d::Zero();

  // Body of mass m with centre of mass c and inertia about the centre of mass Ic, all in world coordinates.
  [[nodiscard]] static SpatialInertia from_body(double m, const Eigen::Vector3d& c,
                                                const Eigen::Matrix3d& inertia_about_com) noexcept {
    SpatialInertia s;
    s.mass = m;
    s.first_moment = m * c;
    // I_O = I_c + m ([c]x [c]x^T) = I_c + m (c^T c 1 - c c^T)
    s.rotational = inertia_about_com + m * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
    return s;
  }

  SpatialInertia& operator+=(const SpatialInertia& o) noexcept {
    mass += o.mass;
    first_moment += o.first_moment;
    rotational += o.rotational;
    return *this;
  }

  // Momentum I v.
  [[nodiscard]] Force operator*(const Motion& v) const noexcept {
    return {rotational * v.angular + first_moment.cross(v.linear), mass * v.linear - first_moment.cross(v.angular)};
  }
};

}  // namespace hapticd::model
