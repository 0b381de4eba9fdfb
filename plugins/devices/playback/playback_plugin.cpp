// Entry points of the playback-device plugin library.
#include "hapticd/plugin.hpp"
#include "playback_device.hpp"

HAPTICD_PLUGIN_LIBRARY(hapticd::describe_plugin<hapticd::playback::PlaybackDevice>(
    "playback", "1.0.0", "replays a recording (hapticd --record): joint positions, velocities, efforts, sensor wrench"))
