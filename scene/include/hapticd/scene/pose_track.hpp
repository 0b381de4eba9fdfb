#pragma once
// An object that a rendering engine moves (docs/haptic-scene.md, "Moving objects"): the engine sends poses at its
// own rate, 30-120 Hz; the loop plays them back at its own, so an update is never felt as a force step.
//
// How: interpolation with a delay of one update interval. When a pose arrives, the object goes from where it is
// rendered at that moment to the new pose over one update interval (position linear, orientation spherical), the
// interval being the time between arrivals (smoothed, 4 to 200 ms): the next pose arrives about as it gets there,
// so the path is continuous - a late or early pose bends it, never breaks it - with each segment's velocity. When
// updates stop, the object stops at the last pose (no extrapolation: an engine that stalls does not throw its objects
// across the hand). The price is one update interval of latency (33 ms at 30 Hz), which a person does not feel as a
// force but would as a step.
//
// publish() on the engine's thread, at() on the loop's; the hand-off is lock-free (realtime::LatestValue) and
// allocates nothing: at() is real-time safe.
#include <Eigen/Geometry>
#include <cstdint>

#include "hapticd/realtime/latest_value.hpp"

namespace hapticd::scene {

struct PoseUpdate {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  std::uint64_t object = 0;  // the object it is for (SceneObject::uid; 0: whichever the track follows)
};

class PoseTrack {
 public:
  struct Played {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // linear, world
  };
  // Not real-time safe to race: call before the loop reads the track.
  void reset(const Eigen::Isometry3d& pose, std::int64_t now_ns) noexcept;
  // The reader's side, real-time safe: starts over at `pose` following `object` (a new object in the track's
  // slot): a pose already published for it is kept, one for another object is dropped.
  void restart(const Eigen::Isometry3d& pose, std::int64_t now_ns, std::uint64_t object = 0) noexcept;
  // Any one writer thread: the engine's newest pose.
  void publish(const PoseUpdate& update) { inbox_.publish(update); }
  // The loop: the pose to render at loop time `now_ns`. Real-time safe.
  Played at(std::int64_t now_ns) noexcept;
  [[nodiscard]] double interval_s() const noexcept { return 1e-9 * interval_ns_; }

 private:
  struct Sample {
    std::int64_t time_ns = 0;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  };
  [[nodiscard]] Played evaluate(std::int64_t now_ns) const noexcept;
  realtime::LatestValue<PoseUpdate> inbox_;
  Sample a_, b_;  // the last two poses, a_ older
  double interval_ns_ = 33e6;
  bool started_ = false;
  std::uint64_t object_ = 0;
};

}  // namespace hapticd::scene
