#pragma once
// What a simulated device knows that a real one cannot measure (Device::simulated_truth): the simulation's true
// state after the last read(), kept apart from the device's outputs, for tests and evaluations - how far the
// estimate is from the truth, what the operator really pushed with.
#include "hapticd/joint_vector.hpp"
#include "hapticd/spatial.hpp"

namespace hapticd {

struct SimulatedTruth {
  double time_s = 0.0;                         // simulated time
  JointVector link_position, link_velocity;    // joint outputs (after the gear and its elasticity)
  JointVector motor_position, motor_velocity;  // motor side, at the joint output's scale
  JointVector friction_torque, motor_torque;   // at the joint output
  Pose handle_pose;                            // world
  Twist handle_twist;                          // world, at the handle point
  Wrench handle_wrench;                        // applied to the handle by what holds it (the operator), world
};

}  // namespace hapticd
