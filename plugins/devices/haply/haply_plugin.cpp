#include "haply_device.hpp"
#include "hapticd/plugin.hpp"

using namespace hapticd;

HAPTICD_PLUGIN_LIBRARY(describe_plugin<plugins::haply::HaplyDevice>(
    "haply", "1.0.0", "Haply Inverse3 (with a VerseGrip) through Haply's Inverse Service (WebSocket, JSON)"))
