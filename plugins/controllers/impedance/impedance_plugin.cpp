// Entry points of the impedance-control library.
#include "hapticd/plugin.hpp"
#include "impedance_controller.hpp"

HAPTICD_PLUGIN_LIBRARY(hapticd::describe_plugin<hapticd::controllers::ImpedanceController>(
    "impedance", "1.0.0", "impedance display: J^T (F_d + force feedback) + gravity compensation"))
