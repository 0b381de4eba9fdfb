#pragma once
// Inverse kinematics for non-redundant chains (and a minimum-norm resolution for redundant ones): one damped
// Newton step per cycle from the previous joint target, q_d += J^+ (x_d - FK(q_d)), which converges within a
// few cycles and then tracks; qd_d = J^+ (xd_d) and qdd_d by numerical differentiation of qd_d (as the thesis's
// computed-torque scheme does). Task rows: translation below 6 joints, else full. The plugin evaluates the
// model at q_d, so it keeps its own model workspace (allocated in configure).
#include <memory>

#include "hapticd/inverse_kinematics.hpp"
#include "hapticd/model/model_data.hpp"
#include "hapticd/signal/differentiator.hpp"

namespace hapticd::ik {

class NewtonIk final : public InverseKinematics {
 public:
  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const PluginContext& context) override;
  Outcome activate(const InverseKinematicsInput& current) override;
  Outcome update(const CycleTime& cycle, const InverseKinematicsInput& input, JointTarget& target) override;
  void deactivate() override {}

 private:
  const model::RobotModel* model_ = nullptr;  // the server's, shared by the chain (PluginContext)
  std::unique_ptr<model::ModelData> data_;
  int handle_ = -1;
  int rows_ = 3;
  int steps_ = 1;
  double damping_ = 1e-6;
  JointVector q_, qd_;
  signal::Differentiator<JointVector> acceleration_;
  model::TaskJacobian jacobian_;
};

}  // namespace hapticd::ik
