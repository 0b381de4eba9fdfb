// Entry points of the admittance virtual-model library.
#include "hapticd/plugin.hpp"
#include "virtual_admittance.hpp"

HAPTICD_PLUGIN_LIBRARY(hapticd::describe_plugin<hapticd::models::VirtualAdmittance>(
    "admittance", "1.0.0", "6-D virtual admittance: operator wrench -> desired handle motion"))
