#include "hapticd/dds/world_validation.hpp"

#include <cmath>

#include "hapticd/dds/conversion.hpp"

namespace hapticd::dds {

namespace {

bool finite(const double* v, int n) noexcept {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

}  // namespace

std::string_view check_world(const hapticd_msg_World& w, const WorldBounds& bounds) noexcept {
  if (!valid_text(w.engine) || text_of(w.engine).empty()) return "the engine's name is malformed";
  if (w.shape_count < 0 || w.shape_count > hapticd_msg_MAX_WORLD_SHAPES) return "the shape count is out of range";
  if (!std::isfinite(w.time_s)) return "the time is not finite";
  for (int i = 0; i < w.shape_count; ++i) {
    const hapticd_msg_WorldShape& s = w.shapes[i];
    if (!valid_text(s.body)) return "a body's name is malformed";
    if (s.shape < hapticd_msg_SHAPE_BOX || s.shape > hapticd_msg_SHAPE_PLANE) return "a shape is of no known kind";
    if (!finite(s.size, 3) || !finite(s.color, 4) || !finite(s.shape_pose.position, 3) ||
        !finite(s.shape_pose.orientation, 4))
      return "a shape has a number that is not finite";
    for (const double x : s.size)
      if (x < 0.0 || x > bounds.max_size_m) return "a shape's size is out of bounds";
    for (const double c : s.color)
      if (c < 0.0 || c > 1.0) return "a colour is out of 0..1";
    const double* p = s.shape_pose.position;
    if (std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) > bounds.max_distance_m) return "a shape is too far away";
    const double* q = s.shape_pose.orientation;
    const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (norm < 0.5 || norm > 2.0) return "an orientation is not a unit quaternion";
  }
  return {};
}

}  // namespace hapticd::dds
