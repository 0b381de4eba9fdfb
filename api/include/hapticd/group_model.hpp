#pragma once
// A group model: group-level logic in a device group's stage (phase (b) of the cycle, docs/multi-device.md). It
// sees the handles of all the group's devices at one instant and answers a force for each handle, which the
// device renders with its environment (an admittance-type virtual model adds it to its environment wrench; other
// schemes apply it through the handle's Jacobian). Bimanual coupling to a shared object is one.
// Real-time methods (activate, update) must not throw, allocate, lock or log, and are not declared noexcept
// (return_code.hpp: the rule for exceptions; a model that throws anyway faults its group's devices only).
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hapticd/cycle_time.hpp"
#include "hapticd/export.hpp"
#include "hapticd/parameters.hpp"
#include "hapticd/return_code.hpp"
#include "hapticd/runtime_request.hpp"
#include "hapticd/spatial.hpp"

namespace hapticd {

// One device of the group at the cycle's instant, world frame (estimated: the same state its chain sees).
struct GroupHand {
  Pose pose;               // the handle
  Twist twist;             // the handle's
  Wrench operator_wrench;  // the operator's on the handle (measured or estimated; zero without a sensor)
  bool running = true;     // false: the device is in its safe mode (its force is not applied)
};

// What the server tells a group model at configure() time besides its parameters.
struct GroupModelContext {
  std::string group_name;
  std::vector<std::string> devices;  // the group's devices, in the order of the hands
  double rate_hz = 2000.0;
  std::filesystem::path config_directory;  // folder of the session file
};

class HAPTICD_API GroupModel : public RuntimeRequests {
 public:
  ~GroupModel() override;

  // Not real-time safe. Validate parameters (ParameterError names the key) and allocate everything.
  virtual void configure(const Parameters& parameters, const GroupModelContext& context) = 0;
  // Real-time safe. Start from the hands where they are (at the group's first cycle).
  virtual Outcome activate(std::span<const GroupHand> hands) = 0;
  // Real-time safe: the force on each handle (world, at the handle point), one per hand.
  virtual Outcome update(const CycleTime& cycle, std::span<const GroupHand> hands,
                         std::span<Eigen::Vector3d> handle_force) = 0;
  // Not real-time safe. Called after the loop has ended.
  virtual void deactivate() = 0;
};

}  // namespace hapticd
