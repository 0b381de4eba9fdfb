#pragma once
#include <stdexcept>

#include "hapticd/chain_signals.hpp"
#include "hapticd/cycle_time.hpp"
#include "hapticd/device_clock.hpp"
#include "hapticd/device_description.hpp"
#include "hapticd/export.hpp"
#include "hapticd/parameters.hpp"
#include "hapticd/plugin_context.hpp"
#include "hapticd/return_code.hpp"
#include "hapticd/runtime_request.hpp"
#include "hapticd/simulated_truth.hpp"

namespace hapticd {

// Thrown by a device's configure() when the device is not there - its vendor's library or service cannot be found
// or reached, no device answers to the name, index or serial number - rather than the session being wrong: the
// server says so and exits with code 4 before anything is powered (a ParameterError or another exception: a
// configuration error, code 2). Key-type exception with a key function: one typeinfo across plugins.
class HAPTICD_API DeviceUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
  ~DeviceUnavailable() override;
};

// A force-feedback device (hardware driver or simulation). Lifecycle:
//   configure -> description -> enable -> [home] -> { read, write, [reset_fault] }* -> disable
// read(), write() and reset_fault() are real-time: no allocation, lock or logging, no exception, and not declared
// noexcept (return_code.hpp: the rule for exceptions; one that escapes anyway is contained to this device, fault
// device_read / device_write, its safe mode). Every step after configure() answers with an Outcome: an error
// carries its reason, which the device's fault shows.
class HAPTICD_API Device : public RuntimeRequests {
 public:
  ~Device() override;

  // Not real-time safe. Validate parameters (ParameterError names the key), allocate, open connections.
  // Must not power the drives.
  virtual void configure(const Parameters& parameters, const PluginContext& context) = 0;
  // Not real-time safe. Valid after configure().
  [[nodiscard]] virtual const DeviceDescription& description() const = 0;
  // Not real-time safe. Power the drives with zero torque and release the brakes (capabilities.brakes). An
  // error leaves the device off: it is held in its safe state with the reason, the session's other devices run.
  virtual Outcome enable() = 0;
  // Not real-time safe; called after enable() and before the first read() when capabilities.homing says the
  // device needs it: find the encoders' reference (an index pulse, an end stop) or calibrate, so that read()
  // reports absolute positions. May move the device slowly and take a while. The default does nothing.
  virtual Outcome home();
  // Real-time safe. Fill the newest sample for the cycle at cycle.time_ns. A simulated device advances its
  // physics to that time under the last written command (zero-order hold).
  virtual Outcome read(const CycleTime& cycle, DeviceState& state) = 0;
  // Real-time safe. Command joint torques, held until the next write(): a joint device's (interface joints). The
  // default refuses (a handle device implements write_handle instead).
  virtual Outcome write(const CycleTime& cycle, const JointCommand& command);
  // Real-time safe. A handle device's (interface handle) command in newtons and newton-metres, held until the next
  // call; the server has made it finite and bounded (its safety layer works on the axes, handle.hpp). The default
  // refuses (a joint device implements write instead).
  virtual Outcome write_handle(const CycleTime& cycle, const HandleCommand& command);
  // Real-time safe; the loop, when a recovery from the safe mode is carried out (the device at rest, zero
  // torque written): clear a latched fault of the drives (a CiA 402 fault reset, a speed monitor's latch) so the
  // chain can run again. An error keeps the device in its safe mode with the reason. The default does nothing.
  virtual Outcome reset_fault();
  // Real-time safe; the loop: the safe mode has brought the device to rest with zero torque (on = true: engage
  // the device's brakes, capabilities.brakes), or a recovery is about to run the chain again (false: release
  // them). The default does nothing.
  virtual Outcome brake(bool on);
  // Not real-time safe. Zero torque, brakes engaged, drives off. Called after the loop has stopped using the
  // device (also after an enable() that failed).
  virtual void disable() = 0;
  // Not real-time safe; after configure(). A device whose SDK or service owns the servo loop (it calls back at its
  // own rate, or answers one state per message) returns its clock: with `server.clock: device` its loop runs one
  // cycle per tick (device_clock.hpp; realtime/tick_signal.hpp is one). Null (the default): the loop's own clock.
  [[nodiscard]] virtual DeviceClock* clock() noexcept;
  // Not real-time safe; the loop thread, or after the loop (tests, evaluations): a simulated device's true state
  // after the last read(). False for hardware (the default).
  virtual bool simulated_truth(SimulatedTruth& out) const;
};

}  // namespace hapticd
