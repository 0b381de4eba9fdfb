// The ViSHaRD10 partitioned solution (plugins/ik/vishard10): its inverse functions reproduce the handle pose,
// they are cyclic where the plain pseudoinverse is not, and the weighted wrist pseudoinverse with the wrist
// criterion and the virtual wall takes the critical wrist motion without reaching the singularity.
#include "vishard10_ik.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <random>

#include "hapticd/chain_signals.hpp"
#include "hapticd/device_description.hpp"
#include "hapticd/model/kinematics.hpp"
#include "hapticd/model/redundancy.hpp"
#include "hapticd/parameters.hpp"
#include "hapticd/plugin_context.hpp"
#include "hapticd/testing/allocation_guard.hpp"
#include "partitioned_solution.hpp"
#include "support/device_models.hpp"
#include "support/test_paths.hpp"

namespace hapticd {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDt = 5e-4;

// The plugin's defaults with some values replaced.
Parameters parameters(const ParameterSchema& schema, const std::vector<std::pair<std::string, ParameterValue>>& given) {
  Parameters p;
  for (const auto& spec : schema.specs())
    if (spec.default_value) p.set(spec.name, *spec.default_value);
  for (const auto& [name, value] : given) p.set(name, value);
  return p;
}

class Vishard10Ik : public ::testing::Test {
 protected:
  void SetUp() override {
    robot_ = std::make_unique<model::RobotModel>(test::load_device_model("vishard10"));
    data_ = std::make_unique<model::ModelData>(*robot_);
    handle_ = robot_->require_frame("handle");
    description_.robot_model_file = hapticd::test::source_dir() + "/config/urdf/vishard10.urdf";
    description_.handle_frame = "handle";
    for (int i = 0; i < 10; ++i) description_.joints.push_back(JointDescription{"j", -1e9, 1e9, 10.0, 50.0, 20.0});
  }
  std::unique_ptr<ik::Vishard10Ik> make(const std::vector<std::pair<std::string, ParameterValue>>& given) {
    auto ik = std::make_unique<ik::Vishard10Ik>();
    PluginContext context;
    context.device = &description_;
    context.robot_model = robot_.get();
    ik->configure(parameters(ik::Vishard10Ik::parameter_schema(), given), context);
    return ik;
  }
  Eigen::Isometry3d fk(const JointVector& q) {
    model::forward_kinematics(*robot_, *data_, q);
    return model::frame_pose(*robot_, *data_, handle_);
  }
  static Pose pose_of(const Eigen::Isometry3d& x) {
    Pose p;
    p.position = x.translation();
    p.orientation = Eigen::Quaterniond(x.linear());
    return p;
  }
  // The posture of the inverse functions for a handle pose near the workspace centre.
  JointVector centre_posture(ik::Vishard10Ik& ik, const Eigen::Vector3d& position, const Eigen::Matrix3d& rotation) {
    Pose p;
    p.position = position;
    p.orientation = Eigen::Quaterniond(rotation);
    return ik.solve(p, Twist{}, kDt);
  }

  std::unique_ptr<model::RobotModel> robot_;
  std::unique_ptr<model::ModelData> data_;
  int handle_ = -1;
  DeviceDescription description_;
};

TEST_F(Vishard10Ik, TheStructureIsReadOffTheModel) {
  const auto g = ik::vishard10::Geometry::from(*robot_, handle_);
  EXPECT_NEAR(g.scara_link[0], 0.25, 1e-12);
  EXPECT_NEAR(g.scara_link[3], 0.25, 1e-12);
  EXPECT_NEAR(g.l67, 0.2122 + 0.2121, 1e-4);
  EXPECT_NEAR(g.z6, 0.1845 + 0.09975 + 0.09525 + 0.0945 + 0.1 + 0.7015, 1e-9);
  // Another device does not pass for a ViSHaRD10.
  const auto v6 = test::load_device_model("vishard6");
  EXPECT_THROW((void)ik::vishard10::Geometry::from(v6, v6.require_frame("handle")), std::invalid_argument);
}

TEST_F(Vishard10Ik, InverseFunctionsReproduceTheHandlePose) {
  auto ik = make({});
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst_position = 0.0, worst_rotation = 0.0;
  for (int k = 0; k < 500; ++k) {
    // Inside the usable box: the SCARA rectangle (|u|, |v| < 0.95 of 0.5 m), heights in the pair's range,
    // orientations with the handle axis away from joint 8's (q9 away from 0 and pi).
    Pose p;
    p.position = Eigen::Vector3d(0.45 * u(rng), 0.45 * u(rng), 1.2755 + 0.35 * u(rng));
    const Eigen::Matrix3d r = ik::vishard10::wrist_rotation(0.0, kPi * u(rng), kPi / 2 + 1.2 * u(rng), kPi * u(rng));
    p.orientation = Eigen::Quaterniond(r);
    const JointVector& q = ik->solve(p, Twist{}, kDt);
    const Eigen::Isometry3d x = fk(q);
    worst_position = std::max(worst_position, (x.translation() - p.position).norm());
    worst_rotation = std::max(worst_rotation, Eigen::AngleAxisd(x.linear() * r.transpose()).angle());
    EXPECT_NEAR(q[6], -2.0 * q[5], 1e-12);  // joints 6 and 7 as a prismatic joint
  }
  std::printf("FK(f(x)) - x over 500 poses: %.2e m, %.2e rad\n", worst_position, worst_rotation);
  EXPECT_LT(worst_position, 1e-9);
  EXPECT_LT(worst_rotation, 1e-9);
  EXPECT_EQ(ik->clamped_cycles(), 0u);
}

TEST_F(Vishard10Ik, InverseFunctionsAreCyclicThePseudoinverseIsNot) {
  // A closed handle path: a 10 cm circle in x-y with a 5 cm height wave and the handle tilting back and forth,
  // driven three times round. The inverse functions bring every joint back; the 10-joint pseudoinverse
  // (velocity level, integrated) comes back with the handle but not with the joints.
  auto ik = make({});
  const Eigen::Vector3d centre(0.05, -0.05, 1.4);
  const Eigen::Matrix3d upright = ik::vishard10::wrist_rotation(0.0, 0.3, kPi / 2, 0.2);
  const auto pose_at = [&](double s) {  // s in [0, 1): one lap
    const double a = 2.0 * kPi * s;
    Pose p;
    p.position = centre + Eigen::Vector3d(0.1 * std::cos(a) - 0.1, 0.1 * std::sin(a), 0.05 * std::sin(2.0 * a));
    p.orientation =
        Eigen::Quaterniond(Eigen::AngleAxisd(0.4 * std::sin(a), Eigen::Vector3d::UnitY()).toRotationMatrix() * upright);
    return p;
  };
  const int steps = 4000;  // 2 s per lap at 2 kHz
  const JointVector start = ik->solve(pose_at(0.0), Twist{}, kDt);
  JointVector q = start;
  // The pseudoinverse integrates from the same posture.
  model::GeneralizedInverse pinv;
  pinv.configure(model::InverseKind::pseudoinverse, 10, JointVector::Ones(10));
  model::TaskJacobian j;
  double function_gap = 0.0;
  for (int lap = 0; lap < 3; ++lap) {
    for (int k = 1; k <= steps; ++k) {
      const Pose p = pose_at(static_cast<double>(k % steps) / steps);
      const JointVector& f = ik->solve(p, Twist{}, kDt);
      if (k == steps) function_gap = std::max(function_gap, (f - start).cwiseAbs().maxCoeff());
      // Pseudoinverse step: qd = J^+ (x_next - x(q)) / dt (closed loop, so the handle follows exactly).
      model::forward_kinematics(*robot_, *data_, q);
      model::frame_jacobian(*robot_, *data_, handle_, j);
      Eigen::Isometry3d next = Eigen::Isometry3d::Identity();
      next.translation() = p.position;
      next.linear() = p.orientation.toRotationMatrix();
      const model::Vector6d e = model::pose_difference(next, model::frame_pose(*robot_, *data_, handle_));
      pinv.compute(j);
      q += pinv.solve(model::TaskVector(e));
    }
  }
  const double handle_gap = (fk(q).translation() - pose_at(0.0).position).norm();
  const double pinv_gap = (q - start).cwiseAbs().maxCoeff();
  std::printf(
      "three laps: inverse functions return to within %.1e rad; the pseudoinverse's handle to %.1e m, its "
      "joints drift by up to %.3f rad\n",
      function_gap, handle_gap, pinv_gap);
  EXPECT_LT(function_gap, 1e-9);
  EXPECT_LT(handle_gap, 1e-6);
  EXPECT_GT(pinv_gap, 1e-3);
}

TEST_F(Vishard10Ik, TheLookupTableReachesTheTipExactlyAndIsCyclic) {
  // The shipped table (config/scara/vishard10.table, made by hapticd-scara-lut): the tip is reached exactly
  // anywhere in its mesh (the elbow is interpolated, both pairs then follow exactly), and a closed path gives a
  // closed joint path.
  const std::string table = hapticd::test::source_dir() + "/config/scara/vishard10.table";
  auto ik = make({{"scara", std::string("lookup_table")}, {"scara_table", table}});
  const auto t = ik::vishard10::ScaraTable::load(table);
  EXPECT_GE(t.tip_speed, 1.0);  // the optimiser's figure for its workspace: the 1 m/s target
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> radius(t.radius_min, t.radius_max), angle(t.angle_min, t.angle_max);
  const Eigen::Matrix3d upright = ik::vishard10::wrist_rotation(0.0, -kPi / 2, kPi / 2, 0.0);
  double worst = 0.0;
  for (int k = 0; k < 500; ++k) {
    Pose p;
    const double r = radius(rng), a = angle(rng);
    p.position = Eigen::Vector3d(r * std::cos(a), r * std::sin(a), 1.45);
    p.orientation = Eigen::Quaterniond(upright);
    worst = std::max(worst, (fk(ik->solve(p, Twist{}, kDt)).translation() - p.position).norm());
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_EQ(ik->clamped_cycles(), 0u);
  // Three laps round a 15 cm circle centred 0.5 m out.
  Pose p;
  p.orientation = Eigen::Quaterniond(upright);
  const auto at = [&](double s) {
    p.position = Eigen::Vector3d(0.5 + 0.15 * std::cos(2 * kPi * s), 0.15 * std::sin(2 * kPi * s), 1.45);
    return ik->solve(p, Twist{}, kDt);
  };
  const JointVector start = at(0.0);
  JointVector q = start;
  for (int k = 1; k <= 3 * 4000; ++k) q = at(static_cast<double>(k % 4000) / 4000);
  std::printf("lookup table: tip reached within %.1e m over 500 positions; three laps close within %.1e rad\n", worst,
              (q - start).cwiseAbs().maxCoeff());
  EXPECT_LT((q - start).cwiseAbs().maxCoeff(), 1e-9);
}

// The critical wrist motion: the handle turns from vertical to horizontal (90 deg in 1 s) about the world y axis,
// 0.15 rad off joint 9's axis (link 5 stands at the yaw 0.15: an operator's motion is never exactly in the
// wrist's plane, where the null space cannot move joint 9 to first order). With link 5 held still joint 9 ends
// at 0.15 rad, next to the singularity. Returns (smallest q9, largest |joint 5
// acceleration|, largest orientation error).
struct WristRun {
  double smallest_q9 = 10.0, largest_q5_acceleration = 0.0, largest_error = 0.0;
};

const Eigen::Vector3d kWristPosition(0.0, 0.0, 1.4);
constexpr double kLink5Yaw = 0.15;
const Eigen::Matrix3d& wrist_start() {  // the handle axis vertical (q8' = -pi/2, q9 = pi/2)
  static const Eigen::Matrix3d r = ik::vishard10::wrist_rotation(kLink5Yaw, -kPi / 2, kPi / 2, 0.0);
  return r;
}

WristRun critical_wrist_motion(ik::Vishard10Ik& ik, const JointVector& start_posture,
                               const std::function<Eigen::Isometry3d(const JointVector&)>& fk) {
  const Eigen::Vector3d& position = kWristPosition;
  const Eigen::Matrix3d& start = wrist_start();
  const Eigen::Vector3d axis9 = Eigen::Vector3d::UnitY();
  Pose p;
  p.position = position;
  p.orientation = Eigen::Quaterniond(start);
  ik.reset(start_posture);  // the integrated parts start from the inverse functions' posture
  WristRun run;
  double q5_previous = 0.0, q5_rate_previous = 0.0;
  const int steps = 2000;
  for (int k = 0; k <= steps + 400; ++k) {
    const double s = std::min(1.0, static_cast<double>(k) / steps);
    const double angle = 0.5 * kPi * (0.5 - 0.5 * std::cos(kPi * s));  // smooth 0 -> 90 deg
    const Eigen::Matrix3d r = Eigen::AngleAxisd(-angle, axis9).toRotationMatrix() * start;
    p.orientation = Eigen::Quaterniond(r);
    Twist w;
    const double rate = k < steps ? 0.5 * kPi * 0.5 * kPi * std::sin(kPi * s) / (steps * kDt) : 0.0;
    w.angular = -rate * axis9;
    const JointVector& q = ik.solve(p, w, kDt);
    run.smallest_q9 = std::min(run.smallest_q9, q[8]);
    const double q5 = q[0] + q[1] + q[2] + q[3] + q[4];
    const double q5_rate = (q5 - q5_previous) / kDt;
    if (k > 1)
      run.largest_q5_acceleration = std::max(run.largest_q5_acceleration, std::abs(q5_rate - q5_rate_previous) / kDt);
    q5_previous = q5;
    q5_rate_previous = q5_rate;
    if (k > 10)
      run.largest_error = std::max(run.largest_error, Eigen::AngleAxisd(fk(q).linear() * r.transpose()).angle());
  }
  return run;
}

TEST_F(Vishard10Ik, TheWristCriterionAndWallKeepTheCriticalMotionAwayFromTheSingularity) {
  const auto fk_of = [&](const JointVector& q) { return fk(q); };
  // The wrist inverse function holds link 5 still: joint 9 goes to 0 with the motion.
  auto function = make({{"q5_0_rad", kLink5Yaw}});
  Pose start;
  start.position = kWristPosition;
  start.orientation = Eigen::Quaterniond(wrist_start());
  const JointVector posture = function->solve(start, Twist{}, kDt);
  const WristRun held = critical_wrist_motion(*function, posture, fk_of);
  // The weighted pseudoinverse with the wrist criterion and the wall turns link 5 (joint 5) instead.
  auto guarded = make({{"wrist", std::string("pseudoinverse")}});
  const WristRun moved = critical_wrist_motion(*guarded, posture, fk_of);
  // Without criterion and wall the pseudoinverse drifts into the singularity too.
  auto bare = make({{"wrist", std::string("pseudoinverse")}, {"wrist_criterion", 0.0}, {"wall_zeta_rad", 0.0}});
  const WristRun free = critical_wrist_motion(*bare, posture, fk_of);
  std::printf(
      "critical wrist motion: smallest q9 %.3f rad (inverse function), %.3f rad (criterion + wall, zeta 0.35), "
      "%.3f rad (bare pseudoinverse); largest joint-5 acceleration %.1f / %.1f / %.1f rad/s^2; orientation "
      "error %.1e / %.1e / %.1e rad\n",
      held.smallest_q9, moved.smallest_q9, free.smallest_q9, held.largest_q5_acceleration,
      moved.largest_q5_acceleration, free.largest_q5_acceleration, held.largest_error, moved.largest_error,
      free.largest_error);
  EXPECT_LT(held.smallest_q9, kLink5Yaw + 1e-6);  // the inverse function ends next to the singularity
  EXPECT_GT(moved.smallest_q9, 0.25);  // the wall holds (it gives 0.07 rad: a spring in the null space, gain 50)
  EXPECT_LT(moved.largest_q5_acceleration, 30.0);  // bounded joint-5 acceleration (gain 200: 0.32 rad, 66 rad/s^2)
  EXPECT_LT(moved.largest_error, 2e-3);            // and the handle still gets its orientation
  EXPECT_LT(free.smallest_q9, moved.smallest_q9);
}

TEST_F(Vishard10Ik, SolvingDoesNotAllocate) {
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "allocation counting unavailable under sanitizers";
  auto function = make({});
  auto pseudo = make({{"wrist", std::string("pseudoinverse")}, {"scara", std::string("pseudoinverse")}});
  Pose p;
  p.position = Eigen::Vector3d(0.1, 0.1, 1.4);
  p.orientation = Eigen::Quaterniond(ik::vishard10::wrist_rotation(0.0, 0.3, 1.2, 0.1));
  (void)function->solve(p, Twist{}, kDt);
  (void)pseudo->solve(p, Twist{}, kDt);
  const std::size_t n = testing::count_allocations([&] {
    for (int k = 0; k < 100; ++k) {
      p.position.x() += 1e-4;
      (void)function->solve(p, Twist{}, kDt);
      (void)pseudo->solve(p, Twist{}, kDt);
    }
  });
  EXPECT_EQ(n, 0u);
}

}  // namespace
}  // namespace hapticd
