// Entry points of the admittance-control library (inner motion loops of admittance display).
#include "hapticd/plugin.hpp"
#include "resolved_acceleration.hpp"

HAPTICD_PLUGIN_LIBRARY(hapticd::describe_plugin<hapticd::controllers::ResolvedAcceleration>(
    "resolved_acceleration", "1.0.0", "admittance display: resolved acceleration control of the handle"))
