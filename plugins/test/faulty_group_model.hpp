#pragma once
#include <atomic>
#include <limits>

#include "hapticd/group_model.hpp"

namespace hapticd::test_plugins {

// A group model that pulls every handle with a constant force and, from cycle `fail_at_cycle` on, fails the way
// `failure` says (error: update returns an error; throw: update throws; nan: a non-finite force): the group
// stage's failure path. Run-time requests (through a device of the group: "group_model.<name>"): force_n is
// tunable, and the command fail_now makes the next cycle fail.
class FaultyGroupModel final : public GroupModel {
 public:
  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const GroupModelContext& context) override;
  Outcome activate(std::span<const GroupHand> hands) override;
  Outcome update(const CycleTime& cycle, std::span<const GroupHand> hands,
                 std::span<Eigen::Vector3d> handle_force) override;
  void deactivate() override {}
  void tune(const Parameters& parameters) override;
  RuntimeReply handle_request(std::string_view name, const std::vector<double>& values) override;

 private:
  enum class Failure { error, exception, nan };
  Failure failure_ = Failure::error;
  std::atomic<std::uint64_t> fail_at_{0};
  std::atomic<double> force_n_{0.0};
};

}  // namespace hapticd::test_plugins
