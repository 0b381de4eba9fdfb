// Out-of-line destructors: the key functions that give each interface one vtable and one type_info, in the
// SDK library, shared by the server and every plugin.
#include "hapticd/controller.hpp"
#include "hapticd/device.hpp"
#include "hapticd/group_model.hpp"
#include "hapticd/inverse_kinematics.hpp"
#include "hapticd/plugin.hpp"
#include "hapticd/scene_service.hpp"
#include "hapticd/virtual_model.hpp"

namespace hapticd {

RuntimeRequests::~RuntimeRequests() = default;
Device::~Device() = default;
DeviceUnavailable::~DeviceUnavailable() = default;
Controller::~Controller() = default;
InverseKinematics::~InverseKinematics() = default;
RedundancyResolution::~RedundancyResolution() = default;
VirtualModel::~VirtualModel() = default;
GroupModel::~GroupModel() = default;
SceneService::~SceneService() = default;

namespace {
RuntimeReply refuse(std::string_view name) {
  return {false, "'" + std::string(name) + "' is not a run-time request this plugin accepts"};
}
void refuse_tuning() {
  throw ParameterError("", "the plugin declares tunable parameters but does not implement tune()");
}
}  // namespace

void RuntimeRequests::tune(const Parameters&) { refuse_tuning(); }
RuntimeReply RuntimeRequests::handle_request(std::string_view name, const std::vector<double>&) { return refuse(name); }
bool Device::simulated_truth(SimulatedTruth&) const { return false; }
Outcome Device::home() { return Outcome::success(); }
Outcome Device::write(const CycleTime&, const JointCommand&) {
  return Outcome::failure("this device takes no joint torques (a handle device: write_handle)");
}
Outcome Device::write_handle(const CycleTime&, const HandleCommand&) {
  return Outcome::failure("this device takes no handle commands (a joint device: write)");
}
Outcome Device::reset_fault() { return Outcome::success(); }
Outcome Device::brake(bool) { return Outcome::success(); }
DeviceClock* Device::clock() noexcept { return nullptr; }

std::string_view to_string(PluginKind kind) noexcept {
  switch (kind) {
    case PluginKind::device:
      return "device";
    case PluginKind::controller:
      return "controller";
    case PluginKind::inverse_kinematics:
      return "inverse_kinematics";
    case PluginKind::virtual_model:
      return "virtual_model";
    case PluginKind::group_model:
      return "group_model";
    case PluginKind::scene:
      return "scene";
  }
  return "unknown";
}

}  // namespace hapticd
