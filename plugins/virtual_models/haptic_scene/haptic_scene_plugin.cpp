// Entry point of the haptic scene virtual-model library.
#include "haptic_scene_model.hpp"
#include "hapticd/plugin.hpp"

HAPTICD_PLUGIN_LIBRARY(hapticd::describe_plugin<hapticd::models::HapticSceneModel>(
    "haptic_scene", "1.0.0", "the haptic scene: a proxy among the shapes of a scene file, at loop rate"))
