#pragma once
// Collision geometry of a robot model, and the distance between two models' geometries: every link is covered by
// capsules (the points within `radius` of a segment), the shape whose distances are exact and cheap. A capsule
// comes from the URDF's <collision> elements (a cylinder becomes the capsule around it, a sphere one of zero
// length, a box the capsule around it along its longest side: all cover the shape) or from the session file.
// Real-time safe after construction: fixed-size storage, no allocation.
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "hapticd/export.hpp"
#include "hapticd/joint_vector.hpp"

namespace hapticd::model {

class RobotModel;
struct ModelData;

struct Capsule {
  std::string link;                             // the URDF link it covers (named in faults and reports)
  int body = -1;                                // the body it moves with (-1: the fixed base)
  Eigen::Vector3d a = Eigen::Vector3d::Zero();  // the segment's ends, in the body's joint frame
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  double radius = 0.0;  // m
};

// The capsules of one model placed in the world at one posture (after forward_kinematics or compute_cycle_terms).
struct PlacedCapsules {
  static constexpr int kMax = 24;
  int count = 0;
  std::array<Eigen::Vector3d, kMax> a, b;
  std::array<double, kMax> radius{};
};

// The closest points of segments p0-p1 and q0-q1 (Ericson, Real-Time Collision Detection, 5.1.9).
struct SegmentPair {
  double distance = 0.0;  // between the segments (not the capsules' surfaces)
  Eigen::Vector3d on_p = Eigen::Vector3d::Zero();
  Eigen::Vector3d on_q = Eigen::Vector3d::Zero();
};
[[nodiscard]] HAPTICD_API SegmentPair closest_points(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                                     const Eigen::Vector3d& q0, const Eigen::Vector3d& q1) noexcept;

// The nearest pair of capsules of two placed sets: the clearance between their surfaces (negative: they overlap)
// and the closest surface points, with the capsules' indices.
struct Clearance {
  double distance = 1e9;  // m between the surfaces; 1e9 when either set is empty
  int capsule_first = -1, capsule_second = -1;
  Eigen::Vector3d point_first = Eigen::Vector3d::Zero();   // on the first set's capsule surface, world
  Eigen::Vector3d point_second = Eigen::Vector3d::Zero();  // on the second set's
  // Unit, from the second capsule's axis to the first's: the way the first moves to gain clearance (x when the
  // axes meet).
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();
};
[[nodiscard]] HAPTICD_API Clearance nearest(const PlacedCapsules& first, const PlacedCapsules& second) noexcept;
// The same for capsule i of the first set and capsule j of the second.
[[nodiscard]] HAPTICD_API Clearance capsule_clearance(const PlacedCapsules& first, int i, const PlacedCapsules& second,
                                                      int j) noexcept;

// Capsules along the kinematic skeleton, for a model whose URDF has no <collision> elements: per body one from
// its joint to the next joint and one to each frame fixed to it (sensor, handle); on the base one from the root
// to the first joint. A rough cover of links whose shapes are unknown; `radius` their thickness.
[[nodiscard]] HAPTICD_API std::vector<Capsule> skeleton_capsules(const RobotModel& model, double radius);

// How a clearance changes with one model's joints: d distance / d q = normal^T J(point), J the linear Jacobian of
// `point` (world) moving with `body` (-1, the fixed base: zero), `normal` the way that point gains clearance. At
// the posture `data` was computed for (forward_kinematics or compute_cycle_terms). Real-time safe.
HAPTICD_API void clearance_gradient(const RobotModel& model, const ModelData& data, int body,
                                    const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
                                    JointVector& gradient) noexcept;

// The model's capsules at the posture `data` was computed for (world frame: the model's, mounted or not).
HAPTICD_API void place_capsules(const RobotModel& model, const ModelData& data, PlacedCapsules& out) noexcept;

}  // namespace hapticd::model
