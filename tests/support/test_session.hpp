#pragma once
// Builds device sessions from session-file text, with the test plugins on the search path.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "assembly/session_impl.hpp"
#include "executor/executor.hpp"
#include "hapticd/server/session.hpp"
#include "session/device_session.hpp"

namespace hapticd::test {

// The device sessions of a session built by build_test_session, for tests that drive them one by one.
inline server::DeviceSession& device_of(server::Session& s, std::size_t i = 0) { return *s.impl().devices.at(i); }

// The k-th cycle of a 2 kHz loop.
inline constexpr std::int64_t kTestPeriodNs = 500'000;
inline CycleTime cycle_at(std::uint64_t k) {
  return CycleTime{static_cast<std::int64_t>(k) * kTestPeriodNs, kTestPeriodNs, k};
}

// Activates the device, runs its first cycle (activation may allocate nothing either, but plugins are allowed
// to warm up there), then counts the allocations of the next `cycles` cycles.
std::size_t allocations_over_cycles(server::DeviceSession& device, std::uint64_t cycles, double torque_scale = 1.0);

// yaml: a whole session file (the public session API, hapticd/server/session.hpp); the test plugins are found
// first.
server::Session build_test_session(const std::string& yaml);

// The configuration error building `yaml` gives (its text), "" when it builds.
std::string config_error_of(const std::string& yaml);

// Runs a built session on its own clock - real time or a device's; lockstep as fast as it goes - as hapticd does
// (its executor and loops); `at` is called once on the calling thread when the loop has run `at_cycle` cycles (the
// executor's monitor: rounds of 20 ms).
server::ExecutorResult run_session(server::Session& s, std::uint64_t at_cycle = 0,
                                   const std::function<void()>& at = {});

// A device entry of the 1-DOF test chain (mass-spring, sine setpoint, axis IK, PD), with extra parameters.
// The flow mapping "{...}" of `base`'s entries ("a: 1, b: [2, 3]") with `overrides`' entries (", b: 4", the
// leading comma optional) in their place or added: a session file gives each key once.
std::string flow_mapping(const std::string& base, const std::string& overrides);
std::string mass_spring_device_yaml(const std::string& name, const std::string& device_parameters = "",
                                    const std::string& controller_parameters = "");

// A lockstep session with one simulated ViSHaRD3 named `name` at its usual start pose with the passive gimbal,
// up to its sim parameters: the caller appends more (8 spaces of indent, e.g. the attachment) and the chain.
std::string sim_vishard3_session_head(const std::string& name, std::uint64_t seed);

// The head of a device entry for the simulated ViSHaRD3 (sim plugin, start pose, passive gimbal, pushed by a
// scripted force `force_profile` of `force_n`); the caller appends more sim parameters (8 spaces of indent)
// and the rest of the chain.
// A simulated device `name` (config/urdf/<model>.urdf, joints at `initial`) pushed by a force step `force_n`
// and a torque step `torque_nm` from 0.2 s on (the `device:` block of a device entry).
std::string sim_wrench_step_device_yaml(const std::string& name, const std::string& model, const std::string& initial,
                                        const std::string& force_n, const std::string& torque_nm);

// The rest of a ViSHaRD3 device entry after its device block: admittance display (3 kg, 40 N s/m, translation)
// with resolved acceleration control.
std::string vishard3_admittance_chain_yaml();

// A lockstep session: the simulated ViSHaRD3 `name` held by the simulated operator, in admittance display (3 kg,
// 40 N s/m, translation) with resolved acceleration control, and a `safety` section with these entries.
std::string sim_vishard3_admittance_session(const std::string& name, std::uint64_t seed,
                                            const std::string& safety = "");

std::string sim_vishard3_device_yaml(const std::string& name, const std::string& force_profile,
                                     const std::string& force_n);

// A simulated ViSHaRD3 device entry at `base` (a base_pose mapping) whose handle a simulated operator holds,
// without its chain (append the virtual model and controller).
std::string sim_vishard3_held_yaml(const std::string& name, const std::string& base);

}  // namespace hapticd::test
