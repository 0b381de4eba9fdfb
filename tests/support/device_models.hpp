#pragma once
// The shipped ViSHaRD models and random joint states for the model toolbox tests.
#include <random>
#include <string>

#include "hapticd/model/robot_model.hpp"
#include "hapticd/model/urdf_loader.hpp"
#include "support/test_paths.hpp"

namespace hapticd::test {

inline const char* const kDeviceModels[] = {"vishard3", "vishard6", "vishard10"};

inline model::RobotModel load_device_model(const std::string& name) {
  return model::load_robot_model(hapticd::test::source_dir() + "/config/urdf/" + name + ".urdf");
}

// Uniform in [-range, range] per joint.
inline JointVector random_joint_vector(std::mt19937_64& rng, int dof, double range) {
  std::uniform_real_distribution<double> u(-range, range);
  JointVector v(dof);
  for (int i = 0; i < dof; ++i) v[i] = u(rng);
  return v;
}

}  // namespace hapticd::test
