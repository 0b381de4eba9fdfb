#include "group/collision_guard.hpp"

#include <algorithm>

#include "hapticd/chain_state.hpp"
#include "hapticd/demand.hpp"
#include "hapticd/model/robot_model.hpp"
#include "session/device_session.hpp"

namespace hapticd::server {

CollisionGuard::CollisionGuard(DeviceSession& first, DeviceSession& second, double min_distance_m)
    : first_(first), second_(second), min_distance_(min_distance_m) {
  HAPTICD_DEMAND(first.chain().robot_model != nullptr && second.chain().robot_model != nullptr);
  const auto& a = first.chain().robot_model->collision();
  const auto& b = second.chain().robot_model->collision();
  second_count_ = static_cast<int>(b.size());
  texts_.reserve(a.size() * b.size());
  for (const auto& ca : a)
    for (const auto& cb : b)
      texts_.push_back("too close: " + first.name() + " " + ca.link + " / " + second.name() + " " + cb.link);
}

void CollisionGuard::run(const CycleTime& cycle) noexcept {
  const ChainState& a = first_.chain_state();
  const ChainState& b = second_.chain_state();
  if (a.data == nullptr || b.data == nullptr) return;
  model::place_capsules(*a.model, *a.data, first_placed_);
  model::place_capsules(*b.model, *b.data, second_placed_);
  clearance_ = model::nearest(first_placed_, second_placed_);
  distance_.store(clearance_.distance, std::memory_order_relaxed);
  if (clearance_.distance < smallest_.load(std::memory_order_relaxed))
    smallest_.store(clearance_.distance, std::memory_order_relaxed);
  if (min_distance_ <= 0.0 || !(clearance_.distance < min_distance_) || clearance_.capsule_first < 0) return;
  const bool first_running = first_.fault() == DeviceFault::none;
  const bool second_running = second_.fault() == DeviceFault::none;
  if (!first_running && !second_running) return;
  const char* reason =
      texts_[static_cast<std::size_t>(clearance_.capsule_first * second_count_ + clearance_.capsule_second)].c_str();
  first_.raise_group_fault(DeviceFault::collision, cycle, reason);
  second_.raise_group_fault(DeviceFault::collision, cycle, reason);
  trips_.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace hapticd::server
