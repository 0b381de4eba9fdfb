// Entry points of the ViSHaRD10 partitioned inverse-kinematics library.
#include "hapticd/plugin.hpp"
#include "vishard10_ik.hpp"

HAPTICD_PLUGIN_LIBRARY(hapticd::describe_plugin<hapticd::ik::Vishard10Ik>(
    "vishard10_ik", "1.0.0",
    "inverse kinematics of the ViSHaRD10: partitioned solution (prismatic pair 6-7, SCARA and wrist by inverse "
    "functions, an optimised look-up table or pseudoinverses)"))
