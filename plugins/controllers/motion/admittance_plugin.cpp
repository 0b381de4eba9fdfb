// Entry points of the admittance-control library (inner motion loops of admittance display).
#include "hapticd/plugin.hpp"
#include "jacobian_control.hpp"
#include "joint_space_control.hpp"
#include "resolved_acceleration.hpp"

using namespace hapticd;
using namespace hapticd::controllers;

HAPTICD_PLUGIN_LIBRARY(
    describe_plugin<ResolvedAcceleration>("resolved_acceleration", "1.0.0",
                                          "admittance display: resolved acceleration control of the handle"),
    describe_plugin<InverseJacobianControl>("inverse_jacobian", "1.0.0",
                                            "admittance display: inverse-Jacobian control, constant joint inertia"),
    describe_plugin<TransposedJacobianControl>("transposed_jacobian", "1.0.0",
                                               "admittance display: transposed-Jacobian control, constant task mass"),
    describe_plugin<ComputedTorqueControl>(
        "computed_torque", "1.0.0", "admittance display: computed torque on the inverse kinematics' joint targets"),
    describe_plugin<JointPdControl>("joint_pd", "1.0.0",
                                    "admittance display: independent joint PD with gravity compensation"))
