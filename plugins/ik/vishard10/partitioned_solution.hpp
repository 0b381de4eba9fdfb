#pragma once
// The ViSHaRD10 partitioned inverse kinematics ([U06] methods 3, "ViSHaRD10 partitioned solution";
// docs/redundancy.md derives it). The axes of joints 5, 8, 9 and 10 meet in the handle point W, so
//   - the height of W is set by joints 6 and 7 alone when they mimic a prismatic joint: q7 = -2 q6,
//     z = z6 + (l6 + l7) cos q6 (q6 <= 0 branch);
//   - the x-y position of W is that of joint 5's axis: joints 1-4 (a planar 4R SCARA arm);
//   - the orientation depends only on q_rot = [q5', q8', q9, q10], q5' = q1 + .. + q5, q8' = q6 + q7 + q8:
//     R = Rz(q5') A Rz(q8') B Rz(q9) C Rz(q10), A = Ry(pi/2) Rz(pi), B = Ry(pi/2), C = Ry(pi/2) Rx(pi).
// The solution pieces here are pure functions; the plugin combines them. Real-time safe.
#include <Eigen/Geometry>
#include <array>

#include "hapticd/joint_vector.hpp"
#include "hapticd/model/model_data.hpp"

namespace hapticd::ik::vishard10 {

// The dimensions the solution needs, read off the model (forward kinematics at q = 0), and a check that the
// model has the structure above (throws std::invalid_argument naming what differs).
struct Geometry {
  Eigen::Vector2d base = Eigen::Vector2d::Zero();  // joint 1's axis
  std::array<double, 4> scara_link{};              // horizontal link lengths 1-4
  double z6 = 0.0;                                 // height of joint 6's axis
  double l67 = 0.0;                                // l6 + l7 (in the plane of joints 6 and 7)
  static Geometry from(const model::RobotModel& model, int handle_frame);
};

// Joints 6 and 7 as one prismatic joint. Outside (z6 - l67, z6 + l67) (|cos q6| > 1 - margin) the height is
// clamped to the boundary; returns false then.
bool prismatic_pair(const Geometry& g, double z, double& q6, double& q7, double margin = 1e-3) noexcept;

// The SCARA inverse function: pair 1-2 as a prismatic joint along the direction `yaw`, pair 3-4 along yaw + pi/2
// (so link 3 keeps its world orientation yaw + pi/2 + psi). branch: +1 or -1 per pair (the elbow side). Fills
// q[0..3]. Its workspace is the rectangle |u|, |v| <= limit (u, v: the pair extensions over their reach 2 l);
// a target outside is clamped to it (returns false then).
bool scara_inverse_function(const Geometry& g, const Eigen::Vector2d& target, double yaw, int branch12, int branch34,
                            double q[4], double limit = 1.0 - 1e-3) noexcept;
// The absolute yaw of link 4 (q1 + .. + q4).
[[nodiscard]] inline double scara_link4_yaw(const double q[4]) noexcept { return q[0] + q[1] + q[2] + q[3]; }

// The 3R wrist for a fixed q5': R -> (q8', q9, q10) with q9 in [0, pi] (sin q9 >= 0 branch). Singular where
// q9 = 0 or pi (the handle axis along joint 8's). Returns q9.
double wrist_inverse_function(const Eigen::Matrix3d& rotation, double q5_abs, double& q8_abs, double& q9,
                              double& q10) noexcept;
// Handle orientation from the wrist angles (the forward map of the above).
[[nodiscard]] Eigen::Matrix3d wrist_rotation(double q5_abs, double q8_abs, double q9, double q10) noexcept;
// The world axes of q5', q8', q9 and q10 (the columns of the wrist's 3 x 4 angular Jacobian), and the handle
// orientation, at these angles.
Eigen::Matrix3d wrist_axes(double q5_abs, double q8_abs, double q9, double q10,
                           Eigen::Matrix<double, 3, 4>& axes) noexcept;

// The joint closest to `previous` among value + 2 pi k (continuous joints: no jump where atan2 wraps).
[[nodiscard]] double unwrap_near(double value, double previous) noexcept;

}  // namespace hapticd::ik::vishard10
