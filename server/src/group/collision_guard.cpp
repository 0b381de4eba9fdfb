#include "group/collision_guard.hpp"

#include <algorithm>

#include "hapticd/demand.hpp"
#include "hapticd/model/robot_model.hpp"
#include "session/device_session.hpp"

namespace hapticd::server {

CollisionGuard::CollisionGuard(DeviceSession& first, DeviceSession& second, double min_distance_m,
                               const RepulsionSettings& repulsion, double period_s)
    : first_(first), second_(second), min_distance_(min_distance_m), repulsion_(repulsion) {
  HAPTICD_DEMAND(first.chain().robot_model != nullptr && second.chain().robot_model != nullptr);
  const auto& a = first.chain().robot_model->collision();
  const auto& b = second.chain().robot_model->collision();
  second_count_ = static_cast<int>(b.size());
  first_filter_.configure(period_s, repulsion.filter_hz);
  second_filter_.configure(period_s, repulsion.filter_hz);
  first_filter_.reset(JointVector::Zero(first.chain().robot_model->dof()));
  second_filter_.reset(JointVector::Zero(second.chain().robot_model->dof()));
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
  // Every pair of capsules: the nearest, and the repulsion of each pair inside its distance (summed, so that the
  // force does not jump when the nearest pair changes).
  clearance_ = model::Clearance{};
  first_torque_.setZero(a.model->dof());
  second_torque_.setZero(b.model->dof());
  double repulsion = 0.0;
  for (int i = 0; i < first_placed_.count; ++i) {
    for (int j = 0; j < second_placed_.count; ++j) {
      const model::Clearance c = model::capsule_clearance(first_placed_, i, second_placed_, j);
      if (c.distance < clearance_.distance) clearance_ = c;
      if (repulsion_.distance_m > 0.0 && c.distance < repulsion_.distance_m) repulsion += repel(a, b, c);
    }
  }
  distance_.store(clearance_.distance, std::memory_order_relaxed);
  repulsion_n_.store(repulsion, std::memory_order_relaxed);
  if (repulsion > largest_repulsion_.load(std::memory_order_relaxed))
    largest_repulsion_.store(repulsion, std::memory_order_relaxed);
  if (clearance_.distance < smallest_.load(std::memory_order_relaxed))
    smallest_.store(clearance_.distance, std::memory_order_relaxed);
  if (clearance_.capsule_first < 0) return;  // either device has no capsules

  // What each device learns: its point of the nearest pair, the way it gains clearance, and how its joints move it.
  first_near_.distance_m = second_near_.distance_m = clearance_.distance;
  first_near_.point = clearance_.point_first;
  first_near_.normal = clearance_.normal;
  second_near_.point = clearance_.point_second;
  second_near_.normal = -clearance_.normal;
  gradients(a, b, clearance_, first_near_.gradient, second_near_.gradient);
  first_.offer_neighbour(first_near_);
  second_.offer_neighbour(second_near_);
  // The point forces act on the joints as the summed torques (low-passed); each handle feels their equivalent.
  if (repulsion_.distance_m > 0.0) {
    const JointVector& first_torque = first_filter_.update(first_torque_);
    const JointVector& second_torque = second_filter_.update(second_torque_);
    if (!first_torque.isZero(1e-9))
      first_.add_group_force(equivalent_handle_force(a, first_torque, repulsion_.max_force_n));
    if (!second_torque.isZero(1e-9))
      second_.add_group_force(equivalent_handle_force(b, second_torque, repulsion_.max_force_n));
  }
  if (min_distance_ > 0.0 && clearance_.distance < min_distance_) trip(cycle);
}

void CollisionGuard::gradients(const ChainState& a, const ChainState& b, const model::Clearance& c, JointVector& first,
                               JointVector& second) const noexcept {
  const int first_body = a.model->collision()[static_cast<std::size_t>(c.capsule_first)].body;
  const int second_body = b.model->collision()[static_cast<std::size_t>(c.capsule_second)].body;
  model::clearance_gradient(*a.model, *a.data, first_body, c.point_first, c.normal, first);
  model::clearance_gradient(*b.model, *b.data, second_body, c.point_second, -c.normal, second);
}

double CollisionGuard::repel(const ChainState& a, const ChainState& b, const model::Clearance& c) noexcept {
  gradients(a, b, c, pair_first_, pair_second_);
  // The pair's clearance rate from both arms' joint velocities (the estimator's).
  const double rate =
      pair_first_.dot(first_.state().joints.velocity) + pair_second_.dot(second_.state().joints.velocity);
  const double f = repulsion_magnitude(repulsion_, c.distance, rate);
  // The point force f * normal acts on the joints as f * (d clearance / d q).
  first_torque_.noalias() += f * pair_first_;
  second_torque_.noalias() += f * pair_second_;
  return f;
}

void CollisionGuard::trip(const CycleTime& cycle) noexcept {
  const bool first_running = first_.status().fault() == DeviceFault::none;
  const bool second_running = second_.status().fault() == DeviceFault::none;
  if (!first_running && !second_running) return;
  const char* reason =
      texts_[static_cast<std::size_t>(clearance_.capsule_first * second_count_ + clearance_.capsule_second)].c_str();
  first_.raise_group_fault(DeviceFault::collision, cycle, reason);
  second_.raise_group_fault(DeviceFault::collision, cycle, reason);
  trips_.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace hapticd::server
