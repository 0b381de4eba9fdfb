// The SCARA look-up table optimiser (plugins/ik/vishard10/scara_lut) on a small mesh: it improves on its own initial
// guess, the figure it reports is the table's, and tables survive a save and load; a broken table file is refused with
// its file and line.
#include "scara_optimiser.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "hapticd/model/urdf_loader.hpp"
#include "support/temp_file.hpp"
#include "support/test_paths.hpp"

namespace hapticd {
namespace {

struct Rig {
  model::RobotModel robot = model::load_robot_model(hapticd::test::source_dir() + "/config/urdf/vishard10.urdf");
  ik::vishard10::Geometry geometry = ik::vishard10::Geometry::from(robot, robot.require_frame("handle"));
  std::array<double, 4> speed{};
  Rig() {
    const JointVector v = robot.speed_limits();
    speed = {v[0], v[1], v[2], v[3]};
  }
};

TEST(ScaraOptimiser, ImprovesOnItsInitialGuessAndReportsTheTablesFigure) {
  Rig rig;
  tools::ScaraWorkspace w;
  w.radius_min = 0.3;
  w.radius_max = 0.6;
  w.radii = 5;
  w.angles = 12;
  tools::ScaraOptimiserSettings s;
  s.radial_lines = 4;
  s.starts_per_line = 3;
  s.norms = {2, 8, 32};
  s.evaluations_per_norm = 200;
  const auto r = tools::optimise_scara_table(rig.geometry, rig.speed, w, s);
  std::printf("small mesh (5 x 12, r 0.3..0.6 m): tip speed %.3f m/s optimised, %.3f m/s initial guess\n",
              r.table.tip_speed, 1.0 / r.initial_worst_rate);
  EXPECT_LE(r.table.worst_rate, r.initial_worst_rate * (1.0 + 1e-9));
  EXPECT_NEAR(tools::worst_normalised_rate(rig.geometry, r.table, rig.speed), r.table.worst_rate, 1e-12);
  EXPECT_NEAR(r.table.tip_speed * r.table.worst_rate, 1.0, 1e-12);
  ASSERT_EQ(r.table.code.size(), 60u);
  for (const auto& c : r.table.code) EXPECT_LE(c.cwiseAbs().maxCoeff(), 1.0);
  // Save and load give the same table.
  const auto file = test::write_temp_file("scara.table", "");
  r.table.save(file, "test table");
  const auto back = ik::vishard10::ScaraTable::load(file);
  EXPECT_EQ(back.radius_count, 5);
  EXPECT_EQ(back.angle_count, 12);
  for (std::size_t k = 0; k < back.code.size(); ++k) EXPECT_EQ(back.code[k], r.table.code[k]);
  EXPECT_DOUBLE_EQ(back.tip_speed, r.table.tip_speed);
}

TEST(ScaraOptimiser, ABrokenTableNamesItsFileAndLine) {
  const auto file = test::write_temp_file("broken.table", "radius 0.3 0.6 2\nangle -1 1 2\ncode 0.1 0.2\ncode 2 0\n");
  try {
    (void)ik::vishard10::ScaraTable::load(file);
    FAIL() << "a code outside [-1, 1] was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("broken.table:4"), std::string::npos) << e.what();
  }
  const auto short_file = test::write_temp_file("short.table", "radius 0.3 0.6 2\nangle -1 1 2\ncode 0.1 0.2\n");
  EXPECT_THROW((void)ik::vishard10::ScaraTable::load(short_file), std::runtime_error);
}

}  // namespace
}  // namespace hapticd
