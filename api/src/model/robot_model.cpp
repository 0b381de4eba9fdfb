#include "hapticd/model/robot_model.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "hapticd/model/model_data.hpp"

namespace hapticd::model {

double DriveData::max_joint_speed() const noexcept {
  return max_input_speed_rpm * 2.0 * std::numbers::pi / 60.0 / gear_ratio;
}

RobotModel::RobotModel(std::string name, std::string source_file, std::vector<Body> bodies, std::vector<Frame> frames,
                       Eigen::Vector3d gravity)
    : name_(std::move(name)),
      source_file_(std::move(source_file)),
      bodies_(std::move(bodies)),
      frames_(std::move(frames)),
      gravity_(std::move(gravity)) {
  if (bodies_.empty() || static_cast<int>(bodies_.size()) > kMaxJoints) {
    throw std::invalid_argument("robot model '" + name_ + "': " + std::to_string(bodies_.size()) +
                                " movable joints; 1.." + std::to_string(kMaxJoints) + " supported");
  }
}

int RobotModel::frame_id(std::string_view frame_name) const noexcept {
  for (std::size_t i = 0; i < frames_.size(); ++i) {
    if (frames_[i].name == frame_name) return static_cast<int>(i);
  }
  return -1;
}

int RobotModel::require_frame(std::string_view frame_name) const {
  const int id = frame_id(frame_name);
  if (id >= 0) return id;
  std::string known;
  for (const auto& f : frames_) known += (known.empty() ? "" : ", ") + f.name;
  throw std::invalid_argument("robot model '" + name_ + "' has no frame '" + std::string(frame_name) +
                              "' (frames: " + known + ")");
}

RobotModel RobotModel::with_gravity(const Eigen::Vector3d& gravity) const {
  RobotModel copy = *this;
  copy.gravity_ = gravity;
  return copy;
}

RobotModel RobotModel::with_base(const Eigen::Isometry3d& base) const {
  // A serial chain: the first body and the frames fixed to the base hang from the root.
  RobotModel copy = *this;
  if (!copy.bodies_.empty()) copy.bodies_.front().placement = base * copy.bodies_.front().placement;
  for (Frame& f : copy.frames_)
    if (f.body < 0) f.placement = base * f.placement;
  for (Capsule& c : copy.capsules_) {
    if (c.body >= 0) continue;
    c.a = base * c.a;
    c.b = base * c.b;
  }
  return copy;
}

RobotModel RobotModel::with_collision(std::vector<Capsule> capsules) const {
  if (capsules.size() > static_cast<std::size_t>(PlacedCapsules::kMax))
    throw std::invalid_argument("robot model '" + name_ + "': " + std::to_string(capsules.size()) +
                                " collision capsules; at most " + std::to_string(PlacedCapsules::kMax));
  for (const Capsule& c : capsules) {
    if (c.body < -1 || c.body >= dof())
      throw std::invalid_argument("robot model '" + name_ + "': a collision capsule of link '" + c.link + "' on body " +
                                  std::to_string(c.body) + ", which the model does not have");
    if (!(c.radius >= 0.0) || !c.a.allFinite() || !c.b.allFinite())
      throw std::invalid_argument("robot model '" + name_ + "': the collision capsule of link '" + c.link +
                                  "' needs finite ends and a radius of at least 0");
  }
  RobotModel copy = *this;
  copy.capsules_ = std::move(capsules);
  return copy;
}

JointVector RobotModel::peak_torques() const {
  JointVector v(dof());
  for (int i = 0; i < dof(); ++i) {
    const Body& b = body(i);
    v[i] = b.drive.present ? b.drive.peak_joint_torque() : b.effort_limit;
  }
  return v;
}

JointVector RobotModel::speed_limits() const {
  JointVector v(dof());
  for (int i = 0; i < dof(); ++i) {
    const Body& b = body(i);
    v[i] = b.drive.present ? b.drive.max_joint_speed() : b.velocity_limit;
  }
  return v;
}

JointVector RobotModel::reflected_inertias() const {
  JointVector v(dof());
  for (int i = 0; i < dof(); ++i) v[i] = body(i).reflected_inertia;
  return v;
}

ModelData::ModelData(const RobotModel& model) : dof(model.dof()) {
  q.setZero(dof);
  qd.setZero(dof);
  mass_matrix.setIdentity(dof, dof);
  mass_llt.compute(mass_matrix);
  gravity_torque.setZero(dof);
  coriolis_torque.setZero(dof);
  scratch.setZero(dof);
  frame_jacobian.setZero(6, dof);
  rotation.fill(Eigen::Matrix3d::Identity());
  position.fill(Eigen::Vector3d::Zero());
}

}  // namespace hapticd::model
