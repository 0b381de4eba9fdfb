#include "eval_options.hpp"

#include "experiment/rig.hpp"

namespace hapticd::eval {

void add_common_options(CLI::App* command, CommonOptions& o, const std::vector<std::string>& devices) {
  command->add_option("--device", o.device, "the simulated device")
      ->check(CLI::IsMember(devices))
      ->capture_default_str();
  command->add_option("--out", o.out, "folder of the results (JSON, PNG, report.html)")->capture_default_str();
  command->add_flag("--quick", o.quick, "a short run of the same protocol (fewer points; what CI runs)");
  command->add_flag("--no-figures", o.no_figures, "write the JSON only (no PNG, no HTML)");
  command->add_option("--seed", o.seed, "the simulation's seed")->capture_default_str();
  command
      ->add_option_function<std::vector<std::string>>(
          "--sim",
          [&o](const std::vector<std::string>& values) {
            for (const std::string& v : values) {
              const auto eq = v.find('=');
              if (eq == std::string::npos || eq == 0) throw CLI::ValidationError("--sim", "KEY=VALUE, got '" + v + "'");
              o.sim_parameters.push_back(v.substr(0, eq) + ": " + v.substr(eq + 1));
            }
          },
          "a simulator parameter for this run, KEY=VALUE (docs/simulated-devices.md); repeatable")
      ->type_name("KEY=VALUE");
  command->add_flag("--no-friction-compensation", o.no_friction_compensation,
                    "admittance display without the friction compensation of the device's identified friction");
}

RigDevice rig_device(const CommonOptions& o) {
  RigDevice d;
  d.name = o.device;
  d.sim_parameters = o.sim_parameters;
  d.friction_compensation = !o.no_friction_compensation;
  return d;
}

void add_scheme_options(CLI::App* command, std::vector<std::string>& schemes, double& virtual_mass_kg) {
  command->add_option("--schemes", schemes, "open-loop, pd:KP:KD, rac:KP[:ff], ijc:KP[:ff], tjc:KP[:ff]")
      ->capture_default_str();
  command->add_option("--virtual-mass", virtual_mass_kg, "admittance display: the rendered mass [kg]")
      ->check(CLI::Range(0.1, 1000.0))
      ->capture_default_str();
}

}  // namespace hapticd::eval
