#include "hapticd/plugin.hpp"
#include "openhaptics_device.hpp"

using namespace hapticd;

HAPTICD_PLUGIN_LIBRARY(describe_plugin<plugins::openhaptics::OpenHapticsDevice>(
    "openhaptics", "1.0.0", "3D Systems Touch and Touch X (OpenHaptics HD API, loaded at run time)"))
