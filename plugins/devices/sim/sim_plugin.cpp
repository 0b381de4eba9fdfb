// Entry points of the simulated-device plugin library.
#include "hapticd/plugin.hpp"
#include "sim_device.hpp"

HAPTICD_PLUGIN_LIBRARY(hapticd::describe_plugin<hapticd::sim::SimDevice>(
    "sim", "1.0.0",
    "simulated haptic device from a URDF with drive data (flexible joints, friction, sensors, operator)"))
