#pragma once
// What the gate asks of a door (docs/architecture.md, "The gate and its doors"). A door - DDS, the engine
// socket, the teleoperation link - translates its wire to the gate's calls (Gate::admit for a command,
// RequestDispatcher::answer for a request) and the gate's output to its wire through this interface. Every
// method has a do-nothing default: a door implements what it carries.
//
// Threads: the sinks are called on the gate's publisher thread (state, group_state), its service thread
// (telemetry, answer_requests, service, the presence checks) or any thread (event, description,
// group_description, fault_report: a door makes those thread-safe). None is called on the loop.
#include <cstdint>

#include "gate/peer.hpp"
#include "hapticd_msg.h"
#include "session/device_snapshot.hpp"

namespace hapticd::server {

class RequestDispatcher;

class Door {
 public:
  virtual ~Door() = default;

  // Which peers this door vouches for (PeerId::door).
  [[nodiscard]] virtual DoorKind kind() const noexcept = 0;

  // Presence (the service thread's claim check, and who may release a stop). Whether the channel a claim or stop
  // was made through is still there (a DDS request writer still matched; a connection still open).
  [[nodiscard]] virtual bool channel_open(const Sender&) const { return false; }
  // Whether the peer shows signs of life (a DDS command writer whose liveliness holds; an open connection).
  [[nodiscard]] virtual bool alive(const PeerId&) { return false; }

  // Requests (service thread): answer those waiting, through the dispatcher.
  virtual void answer_requests(RequestDispatcher&) {}
  // The door's own periodic duties (service thread; at least every 50 ms): e.g. DDS's deadline counts.
  virtual void service() {}

  // Sinks. A device's new state: its snapshot and the data model's message of it (publisher thread).
  virtual void state(std::size_t /*device*/, const DeviceSnapshot&, const hapticd_msg_DeviceState&) {}
  // The last state again, for readers that came late (publisher thread, now and then while the loop waits).
  virtual void repeat_state(const hapticd_msg_DeviceState&) {}
  virtual void group_state(const hapticd_msg_GroupState&, bool /*repeat*/) {}
  virtual void description(const hapticd_msg_DeviceDescription&) {}
  virtual void group_description(const hapticd_msg_GroupDescription&) {}
  virtual void fault_report(const hapticd_msg_FaultReport&) {}
  virtual void telemetry(const hapticd_msg_Telemetry&) {}
  virtual void event(const hapticd_msg_Event&) {}

  // The gate starts the doors after its own threads, and stops them (no more input) before its own.
  virtual void start() {}
  virtual void stop() {}
};

}  // namespace hapticd::server
