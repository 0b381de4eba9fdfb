// Entry points of the Newton inverse-kinematics library.
#include "hapticd/plugin.hpp"
#include "newton_ik.hpp"

HAPTICD_PLUGIN_LIBRARY(hapticd::describe_plugin<hapticd::ik::NewtonIk>(
    "newton_ik", "1.0.0", "inverse kinematics: a damped Newton step per cycle, minimum-norm rates"))
