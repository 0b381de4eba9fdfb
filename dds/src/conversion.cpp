#include "hapticd/dds/conversion.hpp"

#include <chrono>

namespace hapticd::dds {

Pose to_pose(const hapticd_msg_Pose& in) noexcept {
  Pose p;
  p.position = Eigen::Vector3d(in.position[0], in.position[1], in.position[2]);
  p.orientation = Eigen::Quaterniond(in.orientation[0], in.orientation[1], in.orientation[2], in.orientation[3]);
  return p;
}

void to_msg(const Pose& in, hapticd_msg_Pose& out) noexcept {
  for (int i = 0; i < 3; ++i) out.position[i] = in.position[i];
  out.orientation[0] = in.orientation.w();
  out.orientation[1] = in.orientation.x();
  out.orientation[2] = in.orientation.y();
  out.orientation[3] = in.orientation.z();
}

Eigen::Matrix<double, 6, 1> to_vector6(const double (&in)[6]) noexcept {
  Eigen::Matrix<double, 6, 1> v;
  for (int i = 0; i < 6; ++i) v[i] = in[i];
  return v;
}

void to_msg(const Eigen::Matrix<double, 6, 1>& in, double (&out)[6]) noexcept {
  for (int i = 0; i < 6; ++i) out[i] = in[i];
}

void to_msg(const Wrench& in, double (&out)[6]) noexcept {
  for (int i = 0; i < 3; ++i) {
    out[i] = in.force[i];
    out[i + 3] = in.torque[i];
  }
}

void to_msg(const Twist& in, double (&out)[6]) noexcept {
  for (int i = 0; i < 3; ++i) {
    out[i] = in.linear[i];
    out[i + 3] = in.angular[i];
  }
}

std::int64_t wall_clock_ns() noexcept {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace hapticd::dds
