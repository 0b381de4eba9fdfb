// Entry points of the scripted wrench model's library.
#include "hapticd/plugin.hpp"
#include "scripted_wrench_model.hpp"

HAPTICD_PLUGIN_LIBRARY(hapticd::describe_plugin<hapticd::models::ScriptedWrenchModel>(
    "scripted_wrench", "1.0.0",
    "a desired wrench played over time (sine, chirp, steps) for impedance or admittance display"))
