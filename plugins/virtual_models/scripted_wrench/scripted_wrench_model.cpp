#include "scripted_wrench_model.hpp"

#include <stdexcept>

#include "hapticd/chain_state.hpp"
#include "hapticd/render_port.hpp"

namespace hapticd::models {

ParameterSchema ScriptedWrenchModel::parameter_schema() {
  ParameterSchema s = VirtualAdmittance::parameter_schema();  // used in admittance display
  s.string("display", "impedance: the device displays the script; admittance: a virtual admittance renders it")
      .choices({"impedance", "admittance"})
      .default_value(std::string("impedance"));
  s.string("signal", "constant, sine, chirp (linear sweep) or steps (levels held step_s each)")
      .choices({"constant", "sine", "chirp", "steps"})
      .default_value(std::string("sine"));
  s.real_vector("force_n", "force amplitude (world axes): what the environment applies to the operator")
      .unit("N")
      .size(3)
      .default_value(std::vector<double>{0, 0, 0});
  s.real_vector("torque_nm", "torque amplitude (world axes)")
      .unit("N m")
      .size(3)
      .default_value(std::vector<double>{0, 0, 0});
  s.real("start_s", "the script starts this long after the model's first cycle (zero before)")
      .unit("s")
      .minimum(0.0)
      .default_value(0.0);
  s.real("frequency_hz", "sine frequency").unit("Hz").greater_than(0.0).default_value(1.0);
  s.real("chirp_start_hz", "chirp: frequency at its start").unit("Hz").minimum(0.0).default_value(1.0);
  s.real("chirp_end_hz", "chirp: frequency at its end").unit("Hz").minimum(0.0).default_value(60.0);
  s.real("chirp_duration_s", "chirp: length of the sweep (zero after)").unit("s").greater_than(0.0).default_value(10.0);
  s.real_vector("step_levels", "steps: the signal's levels in turn (the last one is kept), at most 32")
      .default_value(std::vector<double>{1.0, 0.0});
  s.real("step_s", "steps: how long each level is held").unit("s").greater_than(0.0).default_value(1.0);
  return s;
}

void ScriptedWrenchModel::configure(const Parameters& p, const PluginContext& context) {
  WrenchScript::Settings settings;
  settings.signal = WrenchScript::parse(p.string("signal"));
  const auto& f = p.real_vector("force_n");
  const auto& t = p.real_vector("torque_nm");
  settings.direction << f[0], f[1], f[2], t[0], t[1], t[2];
  settings.start_s = p.real("start_s");
  settings.frequency_hz = p.real("frequency_hz");
  settings.chirp_start_hz = p.real("chirp_start_hz");
  settings.chirp_end_hz = p.real("chirp_end_hz");
  settings.chirp_duration_s = p.real("chirp_duration_s");
  settings.levels = p.real_vector("step_levels");
  settings.step_s = p.real("step_s");
  try {
    script_.configure(settings);
  } catch (const std::invalid_argument& e) {
    throw ParameterError(settings.signal == WrenchScript::Signal::steps ? "step_levels" : "signal", e.what());
  }
  admittance_display_ = p.string("display") == "admittance";
  if (admittance_display_) {
    admittance_.configure(p, context);
  } else {
    admittance_.configure_environment(p, context);  // impedance display: its walls, on the measured motion
  }
}

void ScriptedWrenchModel::tune(const Parameters& parameters) { admittance_.tune(parameters); }

Outcome ScriptedWrenchModel::activate(const VirtualModelInput& current) {
  started_ = false;
  return admittance_.activate(current);  // impedance display: places walls_relative at the handle
}

Outcome ScriptedWrenchModel::update(const CycleTime& cycle, const VirtualModelInput& input, TaskTarget& target) {
  if (!started_) {
    started_ = true;
    start_ns_ = cycle.time_ns;
  }
  const WrenchScript::Vector6 script = script_.at(1e-9 * static_cast<double>(cycle.time_ns - start_ns_));
  if (admittance_display_) return admittance_.update(cycle, input, target, script);
  // Impedance display: the walls and the engine act on the measured handle motion (the chain's one velocity
  // estimate); the handle is the body an engine's proxy is computed from (the state's target pose).
  admittance_.take_tuning();
  const ChainState& c = input.chain;
  WrenchScript::Vector6 environment = script;
  environment.head<3>() += admittance_.wall_force(c.handle_pose.position, c.handle_twist.linear);
  if (admittance_.takes_engine_input()) {
    WrenchScript::Vector6 port_twist;
    port_twist << c.handle_twist.linear, c.handle_twist.angular;
    // The safety layer's passivity observer and controller on the engine's port, the handle.
    environment += input.render.engine_port(
        admittance_.engine_wrench(input.engine, c.handle_pose.position, c.handle_pose.orientation,
                                  c.handle_twist.linear, c.handle_twist.angular),
        port_twist);
  }
  const WrenchScript::Vector6 rendered = input.render.limit(environment);
  display_on_handle(target, c, rendered);
  return Outcome::success();
}

}  // namespace hapticd::models
