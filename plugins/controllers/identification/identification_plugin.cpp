// Entry points of the identification library.
#include "friction_identification.hpp"
#include "hapticd/plugin.hpp"

HAPTICD_PLUGIN_LIBRARY(hapticd::describe_plugin<hapticd::controllers::FrictionIdentification>(
    "friction_identification", "1.0.0",
    "identifies each joint's friction (break-away, Stribeck curve, load dependency) and writes a friction file"))
