#include "friction_parameters.hpp"

#include <filesystem>
#include <string>

#include "hapticd/model/friction_file.hpp"
#include "hapticd/model/model_data.hpp"
#include "hapticd/model/task_space.hpp"
#include "hapticd/model/urdf_loader.hpp"

namespace hapticd::controllers {

void declare_friction_parameters(ParameterSchema& s) {
  s.boolean("friction_compensation", "add the model's sliding friction in the direction of motion")
      .default_value(false);
  s.string("friction_file",
           "identified friction per joint (written by the friction_identification controller, "
           "e.g. config/sessions/vishard3/identify-friction.yaml); empty: the polynomial "
           "below for every joint")
      .default_value(std::string());
  s.real_vector("friction_polynomial", "p0 .. p4 of the sliding friction [N m vs rad/s] (default: the 26 C curve)")
      .size(5)
      .default_value(std::vector<double>{1.183, 1.008, -0.2642, 0.0487, -0.0037});
  s.real_vector("friction_load", "a0, a1, a2 of the load-dependent friction")
      .size(3)
      .default_value(std::vector<double>{0.0, 0.02, 0.0});
  s.real("friction_velocity_max", "highest identified velocity: the polynomial is held beyond it")
      .unit("rad/s")
      .greater_than(0.0)
      .default_value(5.0);
  s.real("friction_smooth_velocity", "velocity over which the compensation direction blends in")
      .unit("rad/s")
      .greater_than(0.0)
      .default_value(0.05);
  s.real("friction_fraction", "share of the modelled friction compensated")
      .minimum(0.0)
      .maximum(1.0)
      .default_value(0.8);
}

void configure_friction_compensation(const Parameters& p, const PluginContext& context, int dof,
                                     FrictionCompensation& compensation) {
  FrictionModels models{};
  model::FrictionModel base;
  const auto& fp = p.real_vector("friction_polynomial");
  const auto& fl = p.real_vector("friction_load");
  for (std::size_t i = 0; i < 5; ++i) base.p[i] = fp[i];
  for (std::size_t i = 0; i < 3; ++i) base.load[i] = fl[i];
  base.velocity_max = p.real("friction_velocity_max");
  models.fill(base);
  if (!p.string("friction_file").empty()) {
    std::filesystem::path file = p.string("friction_file");
    if (file.is_relative()) file = context.config_directory / file;
    model::FrictionFile f;
    try {
      f = model::read_friction_file(file);
    } catch (const model::ModelError& e) {
      throw ParameterError("friction_file", e.what());
    }
    if (static_cast<int>(f.joints.size()) != dof) {
      throw ParameterError("friction_file", file.string() + " has " + std::to_string(f.joints.size()) +
                                                " joints, the device " + std::to_string(dof));
    }
    for (int i = 0; i < dof; ++i) models[static_cast<std::size_t>(i)] = f.joints[static_cast<std::size_t>(i)];
  }
  compensation.configure(models, p.real("friction_fraction"), p.real("friction_smooth_velocity"));
}

void SlidingFrictionTerm::configure(const Parameters& p, const PluginContext& context) {
  enabled_ = p.boolean("friction_compensation");
  configure_friction_compensation(p, context, context.device != nullptr ? context.device->dof() : 0, compensation_);
}

void SlidingFrictionTerm::add(const ChainState& chain, const JointVector& velocity, int rows,
                              JointVector& torque) const noexcept {
  if (!enabled_) return;
  const JointVector load = chain.data->gravity_torque - model::operator_wrench_torques(chain, rows);
  for (int i = 0; i < torque.size(); ++i) torque[i] += compensation_.torque(i, velocity[i], load[i]);
}

}  // namespace hapticd::controllers
