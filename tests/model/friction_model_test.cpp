// The friction model of the compensators: evaluation, least-squares identification and the parameter file.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <vector>

#include "hapticd/model/friction_file.hpp"
#include "hapticd/model/urdf_loader.hpp"

namespace hapticd::model {
namespace {

const FrictionModel kCurve26{{1.183, 1.008, -0.2642, 0.0487, -0.0037}, {0.0, 0.02, 0.0}, 5.0, 1.3};

TEST(FrictionModel, EvaluatesThePolynomialAndHoldsItBeyondTheIdentifiedRange) {
  EXPECT_NEAR(kCurve26.sliding(0.0), 1.183, 1e-12);
  EXPECT_NEAR(kCurve26.sliding(-1.0), 1.183 + 1.008 - 0.2642 + 0.0487 - 0.0037, 1e-12);
  EXPECT_DOUBLE_EQ(kCurve26.sliding(9.0), kCurve26.sliding(5.0));
  EXPECT_NEAR(kCurve26.magnitude(1.0, -10.0) - kCurve26.sliding(1.0), 0.2, 1e-12);
}

TEST(FrictionModel, LeastSquaresRecoversAKnownCurve) {
  std::vector<FrictionSample> samples;
  for (double v = 0.1; v <= 4.0; v += 0.1) samples.push_back({v, kCurve26.sliding(v), 1.0});
  const auto fit = fit_sliding_friction(samples, FrictionModel{});
  ASSERT_TRUE(fit.has_value());
  for (std::size_t i = 0; i < 5; ++i) EXPECT_NEAR(fit->p[i], kCurve26.p[i], 1e-8) << "p" << i;
  EXPECT_DOUBLE_EQ(fit->velocity_max, samples.back().speed);
}

TEST(FrictionModel, ANarrowSpeedRangeDoesNotExciteTheFit) {
  std::vector<FrictionSample> samples;
  for (int i = 0; i < 4; ++i) samples.push_back({0.1 + 0.1 * i, 1.2, 1.0});
  EXPECT_FALSE(fit_sliding_friction(samples, kCurve26).has_value());
}

TEST(FrictionModel, RegularizationKeepsTheCurveNearThePriorWhereTheDataIsSilent) {
  // Data only below 0.5 rad/s, 5 % lower than the prior: the regularized fit follows the data there and does
  // not run away above it.
  std::vector<FrictionSample> samples;
  for (double v = 0.05; v <= 0.5; v += 0.05) samples.push_back({v, 0.95 * kCurve26.sliding(v), 1.0});
  const auto fit = fit_sliding_friction(samples, kCurve26, 0.01);
  ASSERT_TRUE(fit.has_value());
  for (double v = 0.05; v <= 0.5; v += 0.05) EXPECT_NEAR(fit->sliding(v), 0.95 * kCurve26.sliding(v), 0.03);
}

TEST(FrictionModel, LoadDependencyFit) {
  std::vector<FrictionSample> samples;
  for (double t = 0.0; t <= 20.0; t += 1.0) samples.push_back({t, 0.05 + 0.02 * t + 0.001 * t * t, 1.0});
  const auto a = fit_load_friction(samples);
  ASSERT_TRUE(a.has_value());
  EXPECT_NEAR((*a)[0], 0.05, 1e-9);
  EXPECT_NEAR((*a)[1], 0.02, 1e-9);
  EXPECT_NEAR((*a)[2], 0.001, 1e-10);
}

TEST(FrictionFile, RoundTrips) {
  const std::filesystem::path file = ::testing::TempDir() + "friction_roundtrip.yaml";
  FrictionFile f{"vishard3", {"joint1", "joint2"}, {kCurve26, kCurve26}};
  f.joints[1].p[0] = 0.9;
  write_friction_file(file, f);
  const FrictionFile back = read_friction_file(file);
  EXPECT_EQ(back.device, "vishard3");
  ASSERT_EQ(back.joints.size(), 2u);
  EXPECT_EQ(back.joint_names[1], "joint2");
  EXPECT_NEAR(back.joints[1].p[0], 0.9, 1e-6);
  EXPECT_NEAR(back.joints[0].p[4], -0.0037, 1e-6);
  EXPECT_NEAR(back.joints[0].load[1], 0.02, 1e-6);
  EXPECT_NEAR(back.joints[0].breakaway_nm, 1.3, 1e-6);
}

TEST(FrictionFile, ErrorsNameTheFileLineAndKey) {
  const std::filesystem::path file = ::testing::TempDir() + "friction_bad.yaml";
  std::ofstream(file) << "device: x\njoints:\n  - {name: j1, coulomb: 1.0, viscous: [1, 2, 3, 4]}\n"
                         "  - {name: j2, coulomb: 1.0, viscous: [1, 2, 3]}\n";
  try {
    (void)read_friction_file(file);
    FAIL() << "expected an error";
  } catch (const ModelError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(file.string() + ":4"), std::string::npos) << what;
    EXPECT_NE(what.find("joints[1].viscous"), std::string::npos) << what;
  }
  std::ofstream(file) << "joints:\n  - {name: j1, coulomb: 1.0, viscous: [1, 2, 3, 4], stribeck: 2}\n";
  EXPECT_THROW((void)read_friction_file(file), ModelError);
}

}  // namespace
}  // namespace hapticd::model
