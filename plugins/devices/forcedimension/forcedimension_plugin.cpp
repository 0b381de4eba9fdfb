#include "forcedimension_device.hpp"
#include "hapticd/plugin.hpp"

using namespace hapticd;

HAPTICD_PLUGIN_LIBRARY(describe_plugin<plugins::forcedimension::ForceDimensionDevice>(
    "forcedimension", "1.0.0", "Force Dimension omega, sigma, delta and lambda devices through the vendor's SDK"))
