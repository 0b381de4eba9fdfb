#include "hapticd/scene/pose_track.hpp"

#include <algorithm>

namespace hapticd::scene {

void PoseTrack::reset(const Eigen::Isometry3d& pose, std::int64_t now_ns) noexcept {
  PoseUpdate drained;
  while (inbox_.take(drained)) {
  }
  restart(pose, now_ns);
}

void PoseTrack::restart(const Eigen::Isometry3d& pose, std::int64_t now_ns, std::uint64_t object) noexcept {
  object_ = object;
  a_ = b_ = Sample{now_ns, pose.translation(), Eigen::Quaterniond(pose.linear())};
  interval_ns_ = 33e6;
  started_ = false;
}

PoseTrack::Played PoseTrack::evaluate(std::int64_t now_ns) const noexcept {
  Played out;
  const double span = static_cast<double>(b_.time_ns - a_.time_ns);
  const double rendered = static_cast<double>(now_ns) - interval_ns_;
  const double s = span > 0.0 ? std::clamp((rendered - static_cast<double>(a_.time_ns)) / span, 0.0, 1.0) : 1.0;
  out.pose.translation() = a_.position + s * (b_.position - a_.position);
  out.pose.linear() = a_.orientation.slerp(s, b_.orientation).toRotationMatrix();
  if (span > 0.0 && s < 1.0) out.velocity = (b_.position - a_.position) / (1e-9 * span);
  return out;
}

PoseTrack::Played PoseTrack::at(std::int64_t now_ns) noexcept {
  PoseUpdate update;
  if (inbox_.take(update) && (update.object == 0 || object_ == 0 || update.object == object_)) {
    if (started_)
      interval_ns_ = std::clamp(0.8 * interval_ns_ + 0.2 * static_cast<double>(now_ns - b_.time_ns), 4e6, 200e6);
    started_ = true;
    // The new segment starts where the rendering is now and reaches the new pose one interval later: a late or
    // early pose bends the path, never breaks it.
    const Played here = evaluate(now_ns);
    a_ = Sample{now_ns - static_cast<std::int64_t>(interval_ns_), here.pose.translation(),
                Eigen::Quaterniond(here.pose.linear())};
    b_ = Sample{now_ns, update.position, update.orientation.normalized()};
  }
  return evaluate(now_ns);
}

}  // namespace hapticd::scene
