// Entry points of the trajectory model's library.
#include "hapticd/plugin.hpp"
#include "trajectory_model.hpp"

HAPTICD_PLUGIN_LIBRARY(hapticd::describe_plugin<hapticd::models::TrajectoryModel>(
    "trajectory", "1.0.0", "a desired handle path played over time (motion source for admittance display)"))
