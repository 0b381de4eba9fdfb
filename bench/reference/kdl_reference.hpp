#pragma once
// Orocos KDL as the reference implementation for the model toolbox: a KDL chain built from a RobotModel
// and the KDL solvers for the same quantities. Used by the cross-check tests and the benchmarks only.
#include <kdl/chain.hpp>
#include <kdl/chaindynparam.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacdotsolver.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <memory>

#include "hapticd/model/robot_model.hpp"

namespace hapticd::reference {

// The chain from the base to `frame_id` (a frame on the last body) with every body's inertia. The reflected
// drive inertia is left out (KDL's mass matrix does not include it).
[[nodiscard]] KDL::Chain kdl_chain(const model::RobotModel& model, int frame_id);

// KDL solvers for one chain, allocated once.
struct KdlSolvers {
  explicit KdlSolvers(const model::RobotModel& model, int frame_id);

  KDL::Chain chain;
  KDL::ChainFkSolverPos_recursive fk;
  KDL::ChainJntToJacSolver jacobian;
  KDL::ChainJntToJacDotSolver jacobian_dot;
  KDL::ChainDynParam dynamics;
  KDL::JntArray q, qd, out;
  KDL::JntArrayVel q_qd;
  KDL::Frame pose;
  KDL::Jacobian jac;
  KDL::Twist jac_dot_qd;
  KDL::JntSpaceInertiaMatrix mass;
  KDL::JntArray coriolis, gravity;
};

}  // namespace hapticd::reference
