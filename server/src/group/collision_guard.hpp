#pragma once
// The clearance between two devices of a group, every cycle in the group stage: both devices' collision capsules
// placed at their estimated postures (world frame), the nearest pair of capsules and how the clearance changes
// with each device's joints. With it (docs/multi-device.md):
//   - each device learns its nearest neighbour (ChainState::neighbour): a redundant arm's inverse kinematics moves
//     away from it in the null space;
//   - the repulsion (group/repulsion.hpp) pushes the closest points of every pair of capsules within its distance
//     apart, felt on both handles;
//   - the safety limit: below the group's hard minimum distance both devices enter their safe mode with a fault
//     naming the pair and the links.
// Real-time safe after construction (fixed-size storage; the fault texts are made up front).
#include <atomic>
#include <string>
#include <vector>

#include "group/repulsion.hpp"
#include "hapticd/chain_state.hpp"
#include "hapticd/cycle_time.hpp"
#include "hapticd/model/collision.hpp"
#include "hapticd/signal/differentiator.hpp"

namespace hapticd::server {

class DeviceSession;

class CollisionGuard {
 public:
  // Both devices need a robot model with collision geometry (checked by the session builder). period_s: the
  // loop's (the repulsion's low-pass).
  CollisionGuard(DeviceSession& first, DeviceSession& second, double min_distance_m, const RepulsionSettings& repulsion,
                 double period_s);

  // Phase (b), after both devices were read and estimated.
  void run(const CycleTime& cycle) noexcept;

  [[nodiscard]] const DeviceSession& first() const noexcept { return first_; }
  [[nodiscard]] const DeviceSession& second() const noexcept { return second_; }
  // The latest clearance: where, for the loop thread (and a lockstep caller between steps); how far (m between
  // the capsules' surfaces) and the repulsive force (N, summed over the pairs of capsules inside the repulsion's
  // distance) for any thread.
  [[nodiscard]] const model::Clearance& clearance() const noexcept { return clearance_; }
  [[nodiscard]] double latest_distance() const noexcept { return distance_.load(std::memory_order_relaxed); }
  [[nodiscard]] double latest_repulsion_n() const noexcept { return repulsion_n_.load(std::memory_order_relaxed); }
  // The smallest clearance and the largest repulsion seen so far, and the cycles the hard minimum tripped both
  // devices.
  [[nodiscard]] double smallest_distance() const noexcept { return smallest_.load(std::memory_order_relaxed); }
  [[nodiscard]] double largest_repulsion_n() const noexcept {
    return largest_repulsion_.load(std::memory_order_relaxed);
  }
  [[nodiscard]] std::uint64_t trips() const noexcept { return trips_.load(std::memory_order_relaxed); }

 private:
  void trip(const CycleTime& cycle) noexcept;
  // How the pair's clearance changes with each device's joints.
  void gradients(const ChainState& a, const ChainState& b, const model::Clearance& c, JointVector& first,
                 JointVector& second) const noexcept;
  // Adds the pair's repulsion to both devices' joint torques; returns the force at its points (N).
  double repel(const ChainState& a, const ChainState& b, const model::Clearance& c) noexcept;

  DeviceSession& first_;
  DeviceSession& second_;
  double min_distance_;
  RepulsionSettings repulsion_;
  int second_count_;
  // Per capsule pair ("too close: left link3 / right link2"), made up front: the fault's reason points into it.
  std::vector<std::string> texts_;
  model::PlacedCapsules first_placed_, second_placed_;
  model::Clearance clearance_;
  NeighbourClearance first_near_, second_near_;                // what each device learns (gradients: d clearance / d q)
  JointVector pair_first_, pair_second_;                       // one pair's gradients (repulsion)
  JointVector first_torque_, second_torque_;                   // the repulsion's joint torques, summed over the pairs
  signal::LowPass<JointVector> first_filter_, second_filter_;  // ... low-passed (RepulsionSettings::filter_hz)
  std::atomic<double> distance_{1e9};
  std::atomic<double> repulsion_n_{0.0};
  std::atomic<double> smallest_{1e9};
  std::atomic<double> largest_repulsion_{0.0};
  std::atomic<std::uint64_t> trips_{0};
};

}  // namespace hapticd::server
