// Entry point of the haptic scene library: the virtual model that renders a scene for its device, and the
// session's scene (the `scene` section) that the session's models share and the doors edit. One library, so the
// two share one copy of the scene's code.
#include "haptic_scene_model.hpp"
#include "hapticd/plugin.hpp"
#include "session_scene.hpp"

HAPTICD_PLUGIN_LIBRARY(hapticd::describe_plugin<hapticd::models::HapticSceneModel>(
                           "haptic_scene", "1.0.0",
                           "the haptic scene: a proxy among the shapes of a scene file, at loop rate"),
                       hapticd::describe_plugin<hapticd::models::SessionScene>(
                           "session_scene", "1.0.0",
                           "the session's haptic scene: shared by its devices' haptic_scene models, edited at run "
                           "time"))
