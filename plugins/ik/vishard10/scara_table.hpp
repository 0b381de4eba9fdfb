#pragma once
// The ViSHaRD10 SCARA (joints 1-4) as an inverse function given by a table: for each tip position on a polar mesh
// around the base, the position of the elbow point E between the two link pairs (joint 3's axis). A tip
// position between mesh points gets E by bilinear interpolation in (radius, angle); both pairs then follow
// exactly (two-link inverse kinematics with fixed elbow sides), so the tip is reached exactly and the map is a
// function: cyclic. The table is built off line by plugins/ik/vishard10/scara_lut (numerical optimisation of the worst
// joint rate per tip speed, docs/redundancy.md).
//
// E is coded in [-1, 1]^2 per tip position: s along the chord through the two intersections of the circles of
// reach (radius l1 + l2 around the base, l3 + l4 around the tip), t across it, between the two circles.
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "partitioned_solution.hpp"

namespace hapticd::ik::vishard10 {

// E from its code (s, t) for a tip position; false where the circles of reach do not meet.
bool elbow_from_code(const Geometry& g, const Eigen::Vector2d& tip, double s, double t,
                     Eigen::Vector2d& elbow) noexcept;
// Joints 1-4 with the elbow at E (pairs on the elbow sides branch12, branch34); false if E or the tip is out of
// a pair's reach.
bool scara_joints_from_elbow(const Geometry& g, const Eigen::Vector2d& tip, const Eigen::Vector2d& elbow, int branch12,
                             int branch34, double q[4]) noexcept;

struct ScaraTable {
  // Polar mesh: radius_count radii from radius_min to radius_max, angle_count angles from angle_min to angle_max
  // (the excluded sector lies outside [angle_min, angle_max]).
  double radius_min = 0.0, radius_max = 0.0, angle_min = 0.0, angle_max = 0.0;
  int radius_count = 0, angle_count = 0;
  int branch12 = 1, branch34 = 1;
  std::vector<Eigen::Vector2d> code;  // (s, t) per mesh point, radius-major: index = i_radius * angle_count + i_angle
  // Reported by the optimiser: the worst joint rate per tip speed over the mesh [rad/s per m/s], and the tip speed
  // the joints' speed limits allow.
  double worst_rate = 0.0, tip_speed = 0.0;

  [[nodiscard]] Eigen::Vector2d point(int i_radius, int i_angle) const noexcept;  // the tip position, base frame
  [[nodiscard]] const Eigen::Vector2d& at(int i_radius, int i_angle) const noexcept {
    return code[static_cast<std::size_t>(i_radius * angle_count + i_angle)];
  }

  // Not real-time safe. Throws std::runtime_error naming the file and line.
  static ScaraTable load(const std::filesystem::path& file);
  void save(const std::filesystem::path& file, const std::string& header) const;

  // Real-time safe: the interpolated elbow code for a tip position (relative to the base), the tip clamped into
  // the mesh first (returns false if it had to be).
  bool code_at(const Eigen::Vector2d& tip, Eigen::Vector2d& code, Eigen::Vector2d& clamped_tip) const noexcept;
  // Real-time safe: joints 1-4 for a tip position (relative to the base); a tip outside the mesh is clamped to it
  // (returns false then).
  bool solve(const Geometry& g, const Eigen::Vector2d& tip, double q[4]) const noexcept;
};

}  // namespace hapticd::ik::vishard10
