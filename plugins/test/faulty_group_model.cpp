#include "faulty_group_model.hpp"

#include <stdexcept>

namespace hapticd::test_plugins {

ParameterSchema FaultyGroupModel::parameter_schema() {
  ParameterSchema s;
  s.integer("fail_at_cycle", "the first cycle that fails").minimum(0).default_value(std::int64_t{100});
  s.string("failure", "how it fails").choices({"error", "throw", "nan"}).default_value(std::string("error"));
  s.real("force_n", "the force along x on every handle before it fails").unit("N").default_value(1.0).tunable();
  return s;
}

void FaultyGroupModel::configure(const Parameters& p, const GroupModelContext&) {
  fail_at_ = static_cast<std::uint64_t>(p.integer("fail_at_cycle"));
  const std::string failure = p.string("failure");
  failure_ = failure == "throw" ? Failure::exception : failure == "nan" ? Failure::nan : Failure::error;
  force_n_ = p.real("force_n");
}

void FaultyGroupModel::tune(const Parameters& p) { force_n_ = p.real("force_n"); }

RuntimeReply FaultyGroupModel::handle_request(std::string_view name, const std::vector<double>&) {
  if (name != "fail_now") return {false, "'" + std::string(name) + "' is not a command of this model (fail_now)"};
  fail_at_ = 0;
  return {true, "failing from the next cycle"};
}

Outcome FaultyGroupModel::activate(std::span<const GroupHand>) { return Outcome::success(); }

Outcome FaultyGroupModel::update(const CycleTime& cycle, std::span<const GroupHand>,
                                 std::span<Eigen::Vector3d> handle_force) {
  const bool failing = cycle.index >= fail_at_.load();
  if (failing && failure_ == Failure::error) return Outcome::failure("the test model fails as told");
  if (failing && failure_ == Failure::exception) throw std::runtime_error("a faulty group model");
  for (Eigen::Vector3d& f : handle_force)
    f = failing ? Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN())
                : Eigen::Vector3d(force_n_.load(), 0.0, 0.0);
  return Outcome::success();
}

}  // namespace hapticd::test_plugins
