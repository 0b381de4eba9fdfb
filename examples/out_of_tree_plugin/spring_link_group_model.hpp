// Example group model: a spring between the handles of a group's first two devices (a virtual rope between two
// hands; rest length, stiffness, damping along the line). It sees both handles at the same instant and answers
// equal and opposite forces.
#pragma once
#include <atomic>
#include <hapticd/plugin.hpp>

namespace example {

class SpringLinkGroupModel final : public hapticd::GroupModel {
 public:
  static hapticd::ParameterSchema parameter_schema();

  void configure(const hapticd::Parameters& p, const hapticd::GroupModelContext& context) override;
  hapticd::Outcome activate(std::span<const hapticd::GroupHand> hands) override;
  hapticd::Outcome update(const hapticd::CycleTime& cycle, std::span<const hapticd::GroupHand> hands,
                          std::span<Eigen::Vector3d> handle_force) override;
  void deactivate() override {}
  // stiffness_n_per_m is tunable at run time ("group_model.stiffness_n_per_m" through a device of the group).
  void tune(const hapticd::Parameters& p) override;

 private:
  double rest_m_ = 0.0, damping_ = 0.0;
  std::atomic<double> stiffness_{0.0};  // tune() -> update(): one number, a lock-free atomic
};

}  // namespace example
