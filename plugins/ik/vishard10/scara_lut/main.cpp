// hapticd-scara-lut: builds the ViSHaRD10 SCARA inverse-function look-up table by numerical optimisation
// (scara_optimiser.hpp, docs/redundancy.md), reports the worst joint rate per tip speed for each workspace it
// tries, and writes the table for the chosen one (vishard10_ik reads it: scara: lookup_table).
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>

#include "hapticd/model/urdf_loader.hpp"
#include "scara_optimiser.hpp"

int main(int argc, char** argv) {
  using namespace hapticd;
  CLI::App app{"hapticd-scara-lut: the ViSHaRD10 SCARA look-up table by numerical optimisation"};
  std::string urdf = "config/urdf/vishard10.urdf", output;
  tools::ScaraWorkspace w;
  tools::ScaraOptimiserSettings settings;
  std::vector<double> tries;
  app.add_option("--urdf", urdf, "the ViSHaRD10 model")->capture_default_str();
  app.add_option("--output", output, "write the table for --radius-max here");
  app.add_option("--radius-min", w.radius_min, "inner radius of the workspace [m]")->capture_default_str();
  app.add_option("--radius-max", w.radius_max, "outer radius of the workspace [m]")->capture_default_str();
  app.add_option("--excluded-sector-deg", w.excluded_sector_deg, "width of the sector left out")->capture_default_str();
  app.add_option("--excluded-sector-centre-deg", w.excluded_sector_centre_deg, "its direction")->capture_default_str();
  app.add_option("--radii", w.radii, "mesh: radii")->capture_default_str();
  app.add_option("--angles", w.angles, "mesh: angles")->capture_default_str();
  app.add_option("--try", tries, "also report these outer radii [m]");
  app.add_option("--seed", settings.seed, "multistart seed")->capture_default_str();
  app.add_option("--branch-12", settings.branch12, "elbow side of pair 1-2 (+1, -1)")->capture_default_str();
  app.add_option("--branch-34", settings.branch34, "elbow side of pair 3-4 (+1, -1)")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  try {
    const model::RobotModel robot = model::load_robot_model(urdf);
    const auto geometry = ik::vishard10::Geometry::from(robot, robot.require_frame("handle"));
    const JointVector limits = robot.speed_limits();
    const std::array<double, 4> speed{limits[0], limits[1], limits[2], limits[3]};
    fmt::print("SCARA links {:.3f} {:.3f} {:.3f} {:.3f} m, speed limits {:.2f} {:.2f} {:.2f} {:.2f} rad/s\n",
               geometry.scara_link[0], geometry.scara_link[1], geometry.scara_link[2], geometry.scara_link[3], speed[0],
               speed[1], speed[2], speed[3]);
    // Smallest first: each workspace starts from the table of the one before (warm start).
    tries.push_back(w.radius_max);
    std::sort(tries.begin(), tries.end());
    tries.erase(std::unique(tries.begin(), tries.end()), tries.end());
    ik::vishard10::ScaraTable previous;
    for (double radius : tries) {
      tools::ScaraWorkspace attempt = w;
      attempt.radius_max = radius;
      const auto start = std::chrono::steady_clock::now();
      tools::ScaraOptimiserSettings run = settings;
      if (!previous.code.empty()) run.warm_start = &previous;
      const auto r = tools::optimise_scara_table(geometry, speed, attempt, run);
      previous = r.table;
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      fmt::print(
          "workspace r {:.2f}..{:.2f} m without {:.0f} deg at {:.0f} deg ({} x {} mesh): worst joint rates per tip "
          "speed {:.2f} {:.2f} {:.2f} {:.2f} rad/s per m/s -> tip speed {:.3f} m/s (initial guess {:.3f}{}, two "
          "prismatic pairs {:.3f} m/s); {:.1f} s\n",
          attempt.radius_min, radius, attempt.excluded_sector_deg, attempt.excluded_sector_centre_deg, attempt.radii,
          attempt.angles, r.worst_rate_per_joint[0], r.worst_rate_per_joint[1], r.worst_rate_per_joint[2],
          r.worst_rate_per_joint[3], r.table.tip_speed, 1.0 / r.initial_worst_rate,
          run.warm_start != nullptr ? " warm" : "", 1.0 / r.prismatic_pairs_worst_rate, seconds);
      if (radius == w.radius_max && !output.empty()) {
        std::string warm;
        for (double t : tries)
          if (t < radius) warm += fmt::format(" --try {}", t);
        r.table.save(output,
                     fmt::format("ViSHaRD10 SCARA elbow codes, made by hapticd-scara-lut --radius-min {} "
                                 "--radius-max {} --excluded-sector-deg {} --excluded-sector-centre-deg {} "
                                 "--radii {} --angles {} --seed {}{}\n(each workspace warm-started from the "
                                 "one before)\ntip speed the joint limits allow: {:.3f} m/s",
                                 w.radius_min, w.radius_max, w.excluded_sector_deg, w.excluded_sector_centre_deg,
                                 w.radii, w.angles, settings.seed, warm, r.table.tip_speed));
        fmt::print("wrote {}\n", output);
      }
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "hapticd-scara-lut: {}\n", e.what());
    return 1;
  }
  return 0;
}
