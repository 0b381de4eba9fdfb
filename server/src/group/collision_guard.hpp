#pragma once
// The clearance between two devices of a group, every cycle in the group stage: both devices' collision capsules
// placed at their estimated postures (world frame), the nearest pair of capsules, and the safety limit - below
// the group's hard minimum distance both devices enter their safe mode with a fault naming the pair and the
// links. Real-time safe after construction (fixed-size storage; the fault texts are made up front).
#include <atomic>
#include <string>
#include <vector>

#include "hapticd/cycle_time.hpp"
#include "hapticd/model/collision.hpp"

namespace hapticd::server {

class DeviceSession;

class CollisionGuard {
 public:
  // Both devices need a robot model with collision geometry (checked by the session builder).
  CollisionGuard(DeviceSession& first, DeviceSession& second, double min_distance_m);

  // Phase (b), after both devices were read and estimated.
  void run(const CycleTime& cycle) noexcept;

  [[nodiscard]] const DeviceSession& first() const noexcept { return first_; }
  [[nodiscard]] const DeviceSession& second() const noexcept { return second_; }
  // The latest clearance: where, for the loop thread (and a lockstep caller between steps); how far (m between
  // the capsules' surfaces) for any thread.
  [[nodiscard]] const model::Clearance& clearance() const noexcept { return clearance_; }
  [[nodiscard]] double latest_distance() const noexcept { return distance_.load(std::memory_order_relaxed); }
  // The smallest clearance seen so far, and the cycles the hard minimum tripped both devices.
  [[nodiscard]] double smallest_distance() const noexcept { return smallest_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t trips() const noexcept { return trips_.load(std::memory_order_relaxed); }

 private:
  DeviceSession& first_;
  DeviceSession& second_;
  double min_distance_;
  int second_count_;
  // Per capsule pair ("too close: left link3 / right link2"), made up front: the fault's reason points into it.
  std::vector<std::string> texts_;
  model::PlacedCapsules first_placed_, second_placed_;
  model::Clearance clearance_;
  std::atomic<double> distance_{1e9};
  std::atomic<double> smallest_{1e9};
  std::atomic<std::uint64_t> trips_{0};
};

}  // namespace hapticd::server
