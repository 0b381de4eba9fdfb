#include "hapticd/model/kinematics.hpp"

#include <cmath>

namespace hapticd::model {

void forward_kinematics(const RobotModel& model, ModelData& data, const JointVector& q,
                        BodyInertias inertias) noexcept {
  const int n = model.dof();
  data.q = q;
  Eigen::Matrix3d parent_rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d parent_position = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    const Body& b = model.body(i);
    // Joint frame in the world, before the joint moves.
    Eigen::Matrix3d r = parent_rotation * b.placement.linear();
    Eigen::Vector3d p = parent_position + parent_rotation * b.placement.translation();
    const Eigen::Vector3d axis = r * b.axis;
    Motion& s = data.motion_subspace[i];
    if (b.type == JointType::revolute) {
      r = r * Eigen::AngleAxisd(q[i], b.axis).toRotationMatrix();
      s.angular = axis;
      s.linear = p.cross(axis);
    } else {
      p += axis * q[i];
      s.angular.setZero();
      s.linear = axis;
    }
    data.rotation[i] = r;
    data.position[i] = p;
    if (inertias == BodyInertias::update) {
      const Eigen::Vector3d com = p + r * b.com;
      data.inertia[i] = SpatialInertia::from_body(b.mass, com, r * b.inertia * r.transpose());
    }
    parent_rotation = r;
    parent_position = p;
  }
}

void forward_velocity(const RobotModel& model, ModelData& data, const JointVector& q, const JointVector& qd,
                      BodyInertias inertias) noexcept {
  forward_kinematics(model, data, q, inertias);
  data.qd = qd;
  Motion v;
  Motion a;
  for (int i = 0; i < model.dof(); ++i) {
    const Motion& s = data.motion_subspace[i];
    v += s * qd[i];
    data.velocity[i] = v;
    data.subspace_rate[i] = cross(v, s);
    a += data.subspace_rate[i] * qd[i];
    data.bias_acceleration[i] = a;
  }
}

Eigen::Isometry3d frame_pose(const RobotModel& model, const ModelData& data, int frame_id) noexcept {
  const Frame& f = model.frame(frame_id);
  if (f.body < 0) return f.placement;
  Eigen::Isometry3d body = Eigen::Isometry3d::Identity();
  body.linear() = data.rotation[f.body];
  body.translation() = data.position[f.body];
  return body * f.placement;
}

void frame_jacobian(const RobotModel& model, const ModelData& data, int frame_id, TaskJacobian& jacobian) noexcept {
  const int n = model.dof();
  jacobian.setZero(6, n);
  const Frame& f = model.frame(frame_id);
  const Eigen::Vector3d point = frame_pose(model, data, frame_id).translation();
  for (int j = 0; j <= f.body; ++j) {
    const Motion& s = data.motion_subspace[j];
    // Velocity of `point`: v_O + w x p.
    jacobian.block<3, 1>(0, j) = s.linear + s.angular.cross(point);
    jacobian.block<3, 1>(3, j) = s.angular;
  }
}

namespace {

// The velocity [linear; angular] of the body point at the frame's origin, and the origin itself.
struct PointMotion {
  Eigen::Vector3d point;
  Eigen::Vector3d velocity;
};

PointMotion frame_point_motion(const RobotModel& model, const ModelData& data, int frame_id) noexcept {
  const Eigen::Vector3d point = frame_pose(model, data, frame_id).translation();
  const Motion& v = data.velocity[model.frame(frame_id).body];
  return {point, v.linear + v.angular.cross(point)};  // v_O + w x p
}

}  // namespace

Vector6d frame_velocity(const RobotModel& model, const ModelData& data, int frame_id) noexcept {
  Vector6d twist = Vector6d::Zero();
  const int body = model.frame(frame_id).body;
  if (body < 0) return twist;
  twist.head<3>() = frame_point_motion(model, data, frame_id).velocity;
  twist.tail<3>() = data.velocity[body].angular;
  return twist;
}

Vector6d frame_jacobian_dot_times_qd(const RobotModel& model, const ModelData& data, int frame_id) noexcept {
  Vector6d result = Vector6d::Zero();
  const int body = model.frame(frame_id).body;
  if (body < 0) return result;
  const PointMotion pm = frame_point_motion(model, data, frame_id);
  const Motion& a = data.bias_acceleration[body];
  // Classical acceleration of a body point from the spatial acceleration: a_O + dw x p + w x v_p.
  result.head<3>() = a.linear + a.angular.cross(pm.point) + data.velocity[body].angular.cross(pm.velocity);
  result.tail<3>() = a.angular;
  return result;
}

Vector6d pose_difference(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) noexcept {
  Vector6d d;
  d.head<3>() = a.translation() - b.translation();
  const Eigen::AngleAxisd rotation(a.linear() * b.linear().transpose());
  d.tail<3>() = rotation.axis() * rotation.angle();
  return d;
}

Eigen::Vector3d roll_pitch_yaw(const Eigen::Matrix3d& r) noexcept {
  const double pitch = std::atan2(-r(2, 0), std::hypot(r(0, 0), r(1, 0)));
  const double roll = std::atan2(r(2, 1), r(2, 2));
  const double yaw = std::atan2(r(1, 0), r(0, 0));
  return {roll, pitch, yaw};
}

bool analytic_jacobian(const TaskJacobian& geometric, const Eigen::Matrix3d& rotation, TaskJacobian& analytic,
                       double min_cos_pitch) noexcept {
  const Eigen::Vector3d rpy = roll_pitch_yaw(rotation);
  const double cp = std::cos(rpy[1]);
  if (std::abs(cp) < min_cos_pitch) return false;
  const double sp = std::sin(rpy[1]);
  const double cy = std::cos(rpy[2]);
  const double sy = std::sin(rpy[2]);
  // w = E(rpy) d(rpy)/dt with E = [cy cp, -sy, 0; sy cp, cy, 0; -sp, 0, 1]; its inverse:
  Eigen::Matrix3d e_inv;
  e_inv << cy / cp, sy / cp, 0.0,  //
      -sy, cy, 0.0,                //
      cy * sp / cp, sy * sp / cp, 1.0;
  analytic = geometric;
  analytic.bottomRows<3>() = e_inv * geometric.bottomRows<3>();
  return true;
}

}  // namespace hapticd::model
