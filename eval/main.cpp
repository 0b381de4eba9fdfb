// hapticd-eval: the evaluation suite (off-line; never talks to a running server). The experiments run the
// server's own cycle through the in-process session API in lockstep (docs/evaluation.md).
#include <CLI/CLI.hpp>
#include <cstdlib>
#include <exception>
#include <iostream>

#include "all_command.hpp"
#include "backdrivability_command.hpp"
#include "force_gain_command.hpp"
#include "force_response_command.hpp"
#include "friction_command.hpp"
#include "minimum_inertia_command.hpp"
#include "output_capability_command.hpp"
#include "report/report.hpp"
#include "teleoperation_command.hpp"
#include "tracking_command.hpp"
#include "transparency_command.hpp"
#include "z_width_command.hpp"

int main(int argc, char** argv) {
  CLI::App app{"hapticd-eval: evaluations of haptic devices and control schemes"};
  app.require_subcommand(1);
  int exit_code = 0;
  hapticd::eval::set_command_line(argc, argv);
  hapticd::eval::add_output_capability_command(app, exit_code);
  hapticd::eval::add_backdrivability_command(app, exit_code);
  hapticd::eval::add_force_response_command(app, exit_code);
  hapticd::eval::add_minimum_inertia_command(app, exit_code);
  hapticd::eval::add_force_gain_command(app, exit_code);
  hapticd::eval::add_z_width_command(app, exit_code);
  hapticd::eval::add_tracking_command(app, exit_code);
  hapticd::eval::add_friction_command(app, exit_code);
  hapticd::eval::add_transparency_command(app, exit_code);
  hapticd::eval::add_teleoperation_command(app, exit_code);
  hapticd::eval::add_all_command(app, exit_code);
  const bool parse_only = std::getenv("HAPTICD_PARSE_ONLY") != nullptr;  // the documentation's commands test
  if (parse_only)
    for (CLI::App* command : app.get_subcommands({})) command->callback([] {});
  try {
    app.parse(argc, argv);
    if (parse_only) {
      std::cerr << "hapticd-eval: the command line parsed (HAPTICD_PARSE_ONLY is set: nothing run)\n";
      return 0;
    }
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    std::cerr << "hapticd-eval: " << e.what() << "\n";
    return 2;
  }
  return exit_code;
}
