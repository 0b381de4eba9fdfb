// Entry points of the redundancy-resolution inverse-kinematics library.
#include "hapticd/plugin.hpp"
#include "redundancy_ik.hpp"

HAPTICD_PLUGIN_LIBRARY(hapticd::describe_plugin<hapticd::ik::RedundancyIk>(
    "redundancy_ik", "1.0.0",
    "inverse kinematics for redundant chains: pseudoinverse, weighted, damped or inertia-weighted inverse with "
    "side criteria in the null space"))
