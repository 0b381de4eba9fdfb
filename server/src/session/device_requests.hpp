#pragma once
// The one place that carries out a run-time request to a device (hapticd/server/device_request.hpp). The DDS
// interface's request dispatcher and the in-process session both route through apply_request, so a request
// means the same whichever way it comes. Not real-time, never the loop thread; ownership is the caller's check.
#include "hapticd/runtime_request.hpp"
#include "hapticd/server/device_request.hpp"

namespace hapticd::server {

class DeviceSession;

RuntimeReply apply_request(DeviceSession& device, const DeviceRequest& request);

}  // namespace hapticd::server
