#include "hapticd/model/shared_body.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hapticd::model {

void SharedBody::configure(const SharedBodySettings& settings, double period_s) {
  if (!(settings.mass_kg > 0.0) || !(settings.size_m.minCoeff() > 0.0) || !(period_s > 0.0) || settings.substeps < 1)
    throw std::invalid_argument("the shared body needs a positive mass, size, period and substep count");
  settings_ = settings;
  period_s_ = period_s;
  const Eigen::Vector3d s2 = settings.size_m.cwiseProduct(settings.size_m);
  inertia_body_ =
      (settings.mass_kg / 12.0 * Eigen::Vector3d(s2.y() + s2.z(), s2.x() + s2.z(), s2.x() + s2.y())).asDiagonal();
  const Eigen::Vector3d h = 0.5 * settings.size_m;
  for (int c = 0; c < 8; ++c)
    corners_[static_cast<std::size_t>(c)] =
        Eigen::Vector3d((c & 1) ? h.x() : -h.x(), (c & 2) ? h.y() : -h.y(), (c & 4) ? h.z() : -h.z());
}

void SharedBody::reset(const Pose& pose, std::span<const Eigen::Vector3d> grasp) {
  if (grasp.size() > kMaxHands) throw std::invalid_argument("the shared body takes at most 8 hands");
  position_ = pose.position;
  orientation_ = pose.orientation.normalized();
  velocity_.setZero();
  angular_velocity_.setZero();
  hands_ = grasp.size();
  for (std::size_t k = 0; k < hands_; ++k) {
    grasp_[k] = grasp[k];
    on_body_[k].setZero();
  }
  table_force_.setZero();
}

void SharedBody::step(std::span<const Eigen::Vector3d> hand_position, std::span<const Eigen::Vector3d> hand_velocity,
                      std::span<Eigen::Vector3d> hand_force) noexcept {
  const std::size_t n = std::min({hands_, hand_position.size(), hand_velocity.size()});
  const double dt = period_s_ / settings_.substeps;
  Eigen::Vector3d sum[kMaxHands];
  for (std::size_t k = 0; k < n; ++k) sum[k].setZero();
  for (int s = 0; s < settings_.substeps; ++s) {
    substep(dt, hand_position.first(n), hand_velocity.first(n));
    for (std::size_t k = 0; k < n; ++k) sum[k] += on_body_[k];
  }
  // Each hand feels the reaction of its mean force on the body over the period.
  for (std::size_t k = 0; k < hand_force.size(); ++k)
    hand_force[k] = k < n ? Eigen::Vector3d(-sum[k] / settings_.substeps) : Eigen::Vector3d::Zero();
}

void SharedBody::substep(double dt, std::span<const Eigen::Vector3d> hand_position,
                         std::span<const Eigen::Vector3d> hand_velocity) noexcept {
  const Eigen::Matrix3d R = orientation_.toRotationMatrix();
  Eigen::Vector3d force = settings_.mass_kg * settings_.gravity;
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
  // The hands, each through its coupling at its grasp point.
  for (std::size_t k = 0; k < hand_position.size(); ++k) {
    const Eigen::Vector3d r = R * grasp_[k];
    const Eigen::Vector3d point_velocity = velocity_ + angular_velocity_.cross(r);
    on_body_[k] = settings_.coupling_stiffness_n_per_m * (hand_position[k] - (position_ + r)) +
                  settings_.coupling_damping_n_s_per_m * (hand_velocity[k] - point_velocity);
    force += on_body_[k];
    torque += r.cross(on_body_[k]);
  }
  // The table: a spring-damper on every corner below its plane, and friction against sliding.
  table_force_.setZero();
  if (settings_.table) {
    for (const Eigen::Vector3d& corner : corners_) {
      const Eigen::Vector3d r = R * corner;
      const double depth = settings_.table_height_m - (position_.z() + r.z());
      if (depth <= 0.0) continue;
      const Eigen::Vector3d v = velocity_ + angular_velocity_.cross(r);
      const double normal =
          std::max(0.0, settings_.table_stiffness_n_per_m * depth - settings_.table_damping_n_s_per_m * v.z());
      const Eigen::Vector3d slide(v.x(), v.y(), 0.0);
      const double speed = slide.norm();
      const Eigen::Vector3d friction =
          speed > 0.0 ? Eigen::Vector3d(-settings_.table_friction * normal *
                                        std::min(1.0, speed / settings_.friction_speed_m_s) * slide / speed)
                      : Eigen::Vector3d::Zero();
      const Eigen::Vector3d f = Eigen::Vector3d(0.0, 0.0, normal) + friction;
      table_force_ += f;
      force += f;
      torque += r.cross(f);
    }
  }
  // Semi-implicit Euler: velocities from the forces, then the pose from the new velocities.
  const Eigen::Matrix3d inertia = R * inertia_body_ * R.transpose();
  velocity_ += dt * force / settings_.mass_kg;
  angular_velocity_ += dt * inertia.ldlt().solve(torque - angular_velocity_.cross(inertia * angular_velocity_));
  position_ += dt * velocity_;
  const double angle = angular_velocity_.norm() * dt;
  if (angle > 0.0)
    orientation_ =
        (Eigen::Quaterniond(Eigen::AngleAxisd(angle, angular_velocity_.normalized())) * orientation_).normalized();
}

double SharedBody::internal_force_n() const noexcept {
  if (hands_ < 2) return 0.0;
  const Eigen::Vector3d line = grasp_point(1) - grasp_point(0);
  if (line.norm() <= 0.0) return 0.0;
  const Eigen::Vector3d u = line.normalized();
  return 0.5 * (on_body_[0] - on_body_[1]).dot(u);
}

}  // namespace hapticd::model
