// The MuJoCo engine's scenes (config/scenes/) coupled to their sessions in lockstep (support/coupled_scene.hpp): the
// simulated operator pushes and moves the handle by script; MuJoCo renders the world through the virtual
// coupling, one state period per cycle, exactly as hapticd-mujoco-engine does over DDS. Deterministic: fixed
// seeds, the virtual clock, a fixed number of physics steps per state.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "hapticd/testing/allocation_guard.hpp"
#include "support/coupled_scene.hpp"
#include "support/test_paths.hpp"

namespace hapticd::test {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::string write_scene(const std::string& name, const std::string& xml) {
  const std::string file = ::testing::TempDir() + "/" + name;
  FILE* f = std::fopen(file.c_str(), "w");
  std::fputs(xml.c_str(), f);
  std::fclose(f);
  return file;
}

TEST(MujocoScenes, PushingIntoAFixedBoxSettlesWithTheForcesInBalance) {
  CoupledScene c("table-blocks");
  c.step(200);
  // The hand to just before the fixed box's face (x = +50 mm; the proxy ball has a 10 mm radius), then a 15 N push.
  c.drive("vishard3", "move", {0.035, 0.0, 0.0, 0.5});
  c.step(700);
  c.drive("vishard3", "push", {15.0, 0.0, 0.0, 0.3});
  c.step(2000);
  const mujoco::Proxy p = c.proxy();
  const server::DeviceView v = c.view();
  const double penetration = c.to_scene(p.pose.position).x() + 0.01 - 0.05;
  const double pushed = v.operator_wrench.force.x();
  const double held = -p.contact_force.x();
  std::printf("push %.2f N: the box holds %.2f N (%.1f %%), the proxy %.3f mm into it, the hand %.2f mm past it\n",
              pushed, held, 100.0 * (held - pushed) / pushed, 1e3 * penetration,
              1e3 * (c.to_scene(v.handle_pose.position).x() + 0.01 - 0.05));
  RecordProperty("fixed_box_penetration_mm", std::to_string(1e3 * penetration));
  EXPECT_GT(pushed, 10.0);
  EXPECT_NEAR(held, pushed, 0.05 * pushed);
  EXPECT_LT(penetration, 0.0005);
  EXPECT_GT(penetration, -0.0005);  // in contact
  // The device side: the coupling spring stretched by the push (K = 3000 N/m).
  EXPECT_NEAR(c.to_scene(v.task.pose.position).x() - c.to_scene(p.pose.position).x(), pushed / 3000.0, 0.001);
  EXPECT_EQ(c.unstable_steps(), 0u);
  EXPECT_EQ(v.fault, "");
}

TEST(MujocoScenes, AFreeBlockPushedAcrossTheTableMovesAndStopsByFriction) {
  CoupledScene c("table-blocks");
  c.step(200);
  const Eigen::Vector3d block0 = c.in_scene("block_a");  // 30 mm cube resting on the table at y = +50 mm
  // Down to the block's middle height, then 60 mm along +y through where it stands, then back 30 mm.
  c.drive("vishard3", "move", {0.0, 0.0, -0.025, 0.5});
  c.step(700);
  c.drive("vishard3", "move", {0.0, 0.06, 0.0, 1.0});
  c.step(1300);
  c.drive("vishard3", "move", {0.0, -0.03, 0.0, 0.5});
  c.step(700);
  const Eigen::Vector3d moved = c.in_scene("block_a");
  c.step(500);
  const Eigen::Vector3d rest = c.in_scene("block_a");
  const double speed = c.world().body_twist("block_a")->linear.norm();
  std::printf("the block slid %.1f mm along y (%.1f mm sideways) and stopped: %.3f mm in the last 0.5 s, %.4f m/s\n",
              1e3 * (rest.y() - block0.y()), 1e3 * std::abs(rest.x() - block0.x()), 1e3 * (rest - moved).norm(), speed);
  EXPECT_GT(rest.y() - block0.y(), 0.02);
  EXPECT_LT(rest.y() - block0.y(), 0.045);   // it stops: friction, not a throw
  EXPECT_NEAR(rest.z(), block0.z(), 0.001);  // still on the table
  EXPECT_LT((rest - moved).norm(), 0.0005);
  EXPECT_LT(speed, 1e-3);
  EXPECT_EQ(c.unstable_steps(), 0u);
}

TEST(MujocoScenes, ThePegGoesIntoTheHoleUnderAScriptedHandMotion) {
  CoupledScene c("peg-in-hole");
  c.step(200);
  // Over the hole (30 mm along x), then down 35 mm: the peg's tip (40 mm below the hand) 25 mm into the hole.
  c.drive("vishard3", "move", {0.03, 0.0, 0.0, 0.5});
  c.step(800);
  c.drive("vishard3", "move", {0.0, 0.0, -0.035, 1.0});
  c.step(1800);
  const Eigen::Vector3d peg = c.to_scene(c.proxy().pose.position);
  const double depth = -0.05 - (peg.z() - 0.04);  // the tip below the plate's top
  std::printf("the peg's tip %.1f mm into the hole, %.2f mm / %.2f mm off its axis\n", 1e3 * depth,
              1e3 * (peg.x() - 0.03), 1e3 * peg.y());
  RecordProperty("peg_depth_mm", std::to_string(1e3 * depth));
  EXPECT_GT(depth, 0.015);
  EXPECT_LT(std::abs(peg.x() - 0.03), 0.0011);  // inside the 1 mm clearance
  EXPECT_LT(std::abs(peg.y()), 0.0011);
  EXPECT_EQ(c.unstable_steps(), 0u);
}

TEST(MujocoScenes, APegBesideTheHoleRestsOnThePlate) {
  CoupledScene c("peg-in-hole");
  c.step(200);
  c.drive("vishard3", "move", {0.005, 0.0, 0.0, 0.5});  // 25 mm short of the hole: over the plate
  c.step(800);
  c.drive("vishard3", "move", {0.0, 0.0, -0.035, 1.0});
  c.step(1800);
  const double tip = c.to_scene(c.proxy().pose.position).z() - 0.04;
  std::printf("beside the hole the peg's tip stays %.2f mm above the plate's top\n", 1e3 * (tip + 0.05));
  EXPECT_NEAR(tip, -0.05, 0.0005);
  EXPECT_GT(c.proxy().contact_force.z(), 1.0);  // the plate holds the hand up
}

TEST(MujocoScenes, ThePushedDoorSwingsOpenAndThePushedDrawerSlidesIn) {
  CoupledScene c("door-drawer");
  c.step(200);
  c.drive("vishard3", "move", {0.07, 0.0, 0.0, 1.0});  // through where the door is (x = +47 mm)
  c.step(1500);
  const Eigen::Quaterniond door = c.world().body_pose("door")->orientation;
  const double opened = -180.0 / kPi * 2.0 * std::atan2(door.z(), door.w());
  const Eigen::Vector3d drawer0 = c.in_scene("drawer");
  c.drive("vishard3", "move", {-0.07, 0.0, 0.0, 0.7});  // back
  c.step(900);
  c.drive("vishard3", "move", {-0.08, 0.0, -0.02, 1.0});  // behind the start: into the drawer's front
  c.step(1500);
  const double pushed_in = drawer0.x() - c.in_scene("drawer").x();
  std::printf("the door swung open %.1f degrees; the drawer slid in %.1f mm\n", opened, 1e3 * pushed_in);
  EXPECT_GT(opened, 20.0);
  EXPECT_GT(pushed_in, 0.02);
  EXPECT_LT(pushed_in, 0.0501);  // at most to its stop
  EXPECT_EQ(c.unstable_steps(), 0u);
}

TEST(MujocoScenes, TwoHandsLiftTheBoxFromTheTableAndHoldIt) {
  CoupledScene c("bimanual-box");
  c.step(200);
  const Eigen::Vector3d box0 = c.in_scene("box");
  const double start_gap = (c.to_scene(c.view(1).task.pose.position) - c.to_scene(c.view(0).task.pose.position)).x();
  // Squeeze: each operator pushes 12 N towards the other (along the scene's x: world x for this pair), then both
  // carry half the box's weight on purpose and lift 8 cm over 1 s.
  const Eigen::Vector3d in = c.world().scene_to_world().linear().col(0);
  c.drive("left", "push", {12.0 * in.x(), 12.0 * in.y(), 0.0, 0.3});
  c.drive("right", "push", {-12.0 * in.x(), -12.0 * in.y(), 0.0, 0.3});
  c.step(800);
  const double squeezed = -c.proxy(0).contact_force.dot(in);
  c.drive("left", "push", {12.0 * in.x(), 12.0 * in.y(), 2.45, 0.3});
  c.drive("right", "push", {-12.0 * in.x(), -12.0 * in.y(), 2.45, 0.3});
  c.drive("left", "move", {0.0, 0.0, 0.08, 1.0});
  c.drive("right", "move", {0.0, 0.0, 0.08, 1.0});
  c.step(1500);
  const Eigen::Vector3d lifted = c.in_scene("box");
  c.step(1000);
  const Eigen::Vector3d held = c.in_scene("box");
  std::printf(
      "hands %.1f mm apart at the start; squeezed with %.1f N; the box lifted %.1f mm, %.2f mm lower 1 s later\n",
      1e3 * start_gap, squeezed, 1e3 * (lifted.z() - box0.z()), 1e3 * (lifted.z() - held.z()));
  RecordProperty("bimanual_lift_mm", std::to_string(1e3 * (held.z() - box0.z())));
  EXPECT_GT(squeezed, 5.0);
  EXPECT_GT(held.z() - box0.z(), 0.05);               // off the table (its bottom 50 mm below the hands)
  EXPECT_LT(std::abs(lifted.z() - held.z()), 0.003);  // held, not slipping
  EXPECT_EQ(c.unstable_steps(), 0u);
  EXPECT_EQ(c.view(0).fault, "");
  EXPECT_EQ(c.view(1).fault, "");
}

// A contact-rich run on the table scene: a tap on the table, a slide of a block, a push into the fixed box and back.
double lowest_port_energy(bool passivity_control, double* dissipated = nullptr) {
  CoupledScene c("table-blocks");
  c.passivity_control("vishard3", passivity_control);
  c.step(100);
  for (const auto& [move, cycles] : std::vector<std::pair<std::vector<double>, int>>{
           {{0.0, 0.0, -0.05, 0.3}, 500},  // into the table: the proxy stops on it
           {{0.0, 0.0, 0.025, 0.3}, 400},
           {{0.0, 0.06, 0.0, 0.6}, 800},  // sweeps block_a along
           {{0.0, -0.06, 0.0, 0.4}, 600},
           {{0.07, 0.0, 0.0, 0.3}, 600},  // into the fixed box
           {{-0.07, 0.0, 0.02, 0.3}, 600}}) {
    c.drive("vishard3", "move", move);
    c.step(static_cast<std::uint64_t>(cycles));
  }
  EXPECT_EQ(c.unstable_steps(), 0u);
  EXPECT_EQ(c.view().fault, "");
  if (dissipated != nullptr) *dissipated = c.view().dissipated_j;
  return c.lowest_port_energy_j();
}

TEST(MujocoScenes, ThePortStaysPassiveOverAContactRichRun) {
  double dissipated = 0.0;
  const double without = lowest_port_energy(false);
  const double with = lowest_port_energy(true, &dissipated);
  std::printf(
      "engine port energy at least %.5f J without the passivity controller, %.5f J with it (%.4f J "
      "dissipated)\n",
      without, with, dissipated);
  RecordProperty("lowest_port_energy_j", std::to_string(without));
  // The coupling acts on a one-cycle-old proxy: a little energy comes back from the contacts' stiffness; bounded.
  EXPECT_GT(without, -0.01);
  EXPECT_GT(with, -0.0001);
  EXPECT_GE(with, without);
}

TEST(MujocoScenes, SteppingTheWorldDoesNotAllocate) {
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "allocation counting unavailable under sanitizers";
  CoupledScene c("table-blocks");
  c.step(10);
  std::vector<mujoco::Hand> hands(1);
  hands[0].pose = c.view().task.pose;
  hands[0].pose.position.x() += 0.002;
  const Eigen::Vector3d before = c.proxy().pose.position;
  testing::AllocationGuard guard;
  for (int k = 0; k < 1000; ++k) {
    (void)c.world().step(hands);
    (void)c.world().proxy(0);
  }
  EXPECT_EQ(guard.allocations(), 0u);
  EXPECT_GT((c.proxy().pose.position - before).x(), 0.001);  // it ran: the proxy followed the hand
}

TEST(MujocoScenes, ASceneThatDoesNotFitSaysWhy) {
  const auto error_of = [](const std::string& xml, const std::vector<std::string>& devices) -> std::string {
    const std::string file = write_scene("hapticd_scene.xml", xml);
    try {
      mujoco::CoupledWorld w({file, devices, 1e-3, Eigen::Isometry3d::Identity()});
    } catch (const mujoco::SceneError& e) {
      return e.what();
    }
    return "";
  };
  // Malformed XML, a bad attribute: MuJoCo's message names the line.
  EXPECT_NE(
      error_of("<mujoco>\n<worldbody>\n<body name='proxy'>\n</worldbody>\n</mujoco>\n", {"v3"}).find("Line number=3"),
      std::string::npos);
  EXPECT_NE(error_of("<mujoco>\n<worldbody>\n<geom type='box' size='1'/>\n<body name='p' pos='a b c'/>\n"
                     "</worldbody>\n</mujoco>\n",
                     {"v3"})
                .find("line 4"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><worldbody><body name='ball'><freejoint/><geom size='0.01'/></body></worldbody>"
                     "</mujoco>",
                     {"v3"})
                .find("no proxy body for device 'v3'"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><worldbody><body name='proxy'><geom size='0.01'/></body></worldbody></mujoco>", {"v3"})
                .find("a free joint"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><worldbody><body name='proxy_a'><freejoint/><geom size='0.01'/></body></worldbody>"
                     "</mujoco>",
                     {"a", "b"})
                .find("'proxy_b'"),
            std::string::npos);
  EXPECT_NE(error_of("", {"v3"}), "");
  // A proxy too light for the coupling's gains at the physics step: set_gains refuses, saying what to change.
  const std::string file = write_scene(
      "hapticd_light_proxy.xml",
      "<mujoco><worldbody><body name='proxy'><freejoint/><geom size='0.01' mass='0.001'/></body></worldbody></mujoco>");
  mujoco::CoupledWorld light({file, {"v3"}, 1e-3, Eigen::Isometry3d::Identity()});
  try {
    light.set_gains(0, mujoco::CouplingGains{3000.0, 30.0, 0.0, 0.0});
    ADD_FAILURE() << "a 1 g proxy on a 3000 N/m, 30 N s/m coupling at 1 ms was accepted";
  } catch (const mujoco::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("too light"), std::string::npos) << e.what();
  }
  light.set_gains(0, mujoco::CouplingGains{100.0, 0.5, 0.0, 0.0});  // resolved: accepted
  EXPECT_NE(error_of("<mujoco><worldbody><body name='proxy'><freejoint/><geom size='0.01'/></body></worldbody>"
                     "</mujoco>",
                     {})
                .find("no device"),
            std::string::npos);
}

TEST(MujocoScenes, TheViSHaRD10LaysItsHandOnTheWorkTable) {
  CoupledScene c("vishard10-workspace");
  c.step(400);
  c.drive("vishard10", "move", {0.0, 0.0, -0.08, 1.0});  // 80 mm down: the table's top is 60 mm below the start
  c.step(3000);
  const Eigen::Vector3d proxy = c.to_scene(c.proxy().pose.position);
  const Eigen::Vector3d hand = c.to_scene(c.view().task.pose.position);
  std::printf(
      "ViSHaRD10: the proxy rests at z = %.2f mm (the table's top + its radius: -45.00 mm), the hand at %.2f mm;"
      " the table holds %.2f N\n",
      1e3 * proxy.z(), 1e3 * hand.z(), c.proxy().contact_force.z());
  EXPECT_NEAR(proxy.z(), -0.045, 0.0005);
  EXPECT_LT(hand.z(), proxy.z() - 0.001);  // pressed into the table through the coupling
  EXPECT_GT(c.proxy().contact_force.z(), 2.0);
  EXPECT_EQ(c.unstable_steps(), 0u);
  EXPECT_EQ(c.view().fault, "");
}

TEST(MujocoScenes, WhenTheWorldGoesUnstableTheProxyIsPutAtTheHand) {
  // A scene with a spring far too stiff for the step (a hinge of 1e9 N m/rad on a light rod, released 0.1 rad from
  // its rest): MuJoCo finds a bad acceleration within a few steps and resets the world to its initial state. The
  // proxy must not jump back to where the scene put it (the coupling would pull the hand there): it is put at the
  // hand, at rest, in the same step (hapticd-mujoco-engine then releases the device and ends).
  const std::string file = write_scene(
      "hapticd_unstable.xml",
      "<mujoco><worldbody><body name='proxy'><freejoint/><geom size='0.01' mass='0.05'/></body>"
      "<body name='rod' pos='0.2 0 0'>"
      "<joint name='spring' type='hinge' axis='0 0 1' stiffness='1e9' ref='0.1' springref='0'/>"
      "<geom type='capsule' fromto='0 0 0 0.05 0 0' size='0.002' mass='0.001'/></body></worldbody></mujoco>");
  mujoco::CoupledWorld w({file, {"v3"}, 1e-3, Eigen::Isometry3d::Identity()});
  w.set_gains(0, mujoco::CouplingGains{2000.0, 20.0, 0.0, 0.0});
  mujoco::Hand hand;
  hand.pose.position = Eigen::Vector3d(0.03, -0.01, 0.02);
  w.place(0, hand);
  const std::vector<mujoco::Hand> hands = {hand};
  int k = 0;
  bool stable = true;
  while (stable && k++ < 100) stable = w.step(hands).stable;
  ASSERT_FALSE(stable) << "the world stayed stable";
  const mujoco::Proxy p = w.proxy(0);
  std::printf("the world went unstable at step %d: the proxy %.6f mm from the hand, at %.6f m/s\n", k,
              1e3 * (p.pose.position - hand.pose.position).norm(), p.twist.linear.norm());
  EXPECT_LT((p.pose.position - hand.pose.position).norm(), 1e-9);  // not at the scene's start (36 mm away)
  EXPECT_LT(p.twist.linear.norm(), 1e-9);
}

TEST(MujocoScenes, AProxyThatRunsAwayIsPutAtTheHand) {
  // The hand half a metre from the proxy at once (a server restarted elsewhere, a bad state): the coupling would
  // fling the proxy (2000 N/m on 50 g); faster than 3 m/s it counts as unstable and goes to the hand, at rest.
  const std::string file =
      write_scene("hapticd_runaway.xml",
                  "<mujoco><worldbody><body name='proxy'><freejoint/><geom size='0.01' mass='0.05'/></body>"
                  "</worldbody></mujoco>");
  mujoco::CoupledWorld w({file, {"v3"}, 1e-3, Eigen::Isometry3d::Identity()});
  w.set_gains(0, mujoco::CouplingGains{2000.0, 20.0, 0.0, 0.0});
  std::vector<mujoco::Hand> hands(1);
  EXPECT_TRUE(w.step(hands).stable);
  hands[0].pose.position = Eigen::Vector3d(0.5, 0.0, 0.0);
  EXPECT_FALSE(w.step(hands).stable);
  EXPECT_LT((w.proxy(0).pose.position - hands[0].pose.position).norm(), 1e-9);
  EXPECT_TRUE(w.step(hands).stable);  // from there on, at rest at the hand
}

TEST(MujocoScenes, TheArmItselfPushesABlock) {
  // table-arm.xml: the table scene with the ViSHaRD3's three links as kinematic capsules (from its robot model at the
  // measured joints) and a block 5 mm clear of the last link. The hand moves 30 mm along x: the proxy touches
  // nothing, the link sweeps into the block and pushes it.
  CoupledScene c("table-arm", {}, "table-blocks.yaml");
  ASSERT_EQ(c.world().arm_bodies(0), 3u);
  c.step(200);
  const Eigen::Vector3d block0 = c.in_scene("block_arm");
  EXPECT_LT((block0 - Eigen::Vector3d(0.128, -0.094, -0.025)).norm(), 1e-4);  // clear of the arm at the start
  c.drive("vishard3", "move", {0.03, 0.0, 0.0, 0.8});  // short of the fixed box (its face 40 mm ahead of the ball)
  double touched = 0.0;
  for (int k = 0; k < 1200; ++k) {
    c.step(1);
    touched = std::max(touched, c.proxy().contact_force.norm());
  }
  const Eigen::Vector3d moved = c.in_scene("block_arm") - block0;
  std::printf("the arm's last link pushed the block %.1f mm (along x %.1f mm); the proxy touched nothing (%.2f N)\n",
              1e3 * moved.norm(), 1e3 * moved.x(), touched);
  EXPECT_GT(moved.norm(), 0.005);
  EXPECT_GT(moved.x(), 0.0);
  EXPECT_EQ(touched, 0.0);
  EXPECT_EQ(c.unstable_steps(), 0u);
  // Without the arm's bodies (the same scene in table-blocks.xml) the block would have stayed: nothing else moves it.
}

}  // namespace
}  // namespace hapticd::test
