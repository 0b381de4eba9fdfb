#pragma once
// The gate's requests, on its service thread, from whichever door they came through: each request is answered by
// the handler of its kind (claim, release, switch scheme, set parameter, operator, E-stop, recover, describe; for a
// device group: claim all or none, release, E-stop, recover all or none). The requester is the peer the door
// vouches for (a DDS participant, a connection), whatever client id the request declares; owner-only requests
// (release, switch, set) are accepted only from the claimant, or on a free device; anyone may stop a device, and
// a stop latches until its requester recovers it (StopLatches); a fault without a latched stop is recovered by the
// owner (or anyone on a free device). A request sent again (the same client and request id from the same peer) is
// answered again and not applied twice (AnsweredRequests). The same thread ends claims whose claimant is gone
// (asking the claimant's door: Door::channel_open, Door::alive).
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gate/answered_requests.hpp"
#include "gate/device_gate.hpp"
#include "gate/door.hpp"
#include "gate/event_fanout.hpp"
#include "gate/state_fanout.hpp"
#include "session/device_requests.hpp"

namespace hapticd::server {

class RequestDispatcher {
 public:
  RequestDispatcher(DeviceGates& devices, EventFanout& events, StateFanout& publisher, double claim_grace_s,
                    double claim_hold_s, bool tuning_by_anyone = false);
  // Before any request: the doors, which vouch for their peers' presence.
  void set_doors(const std::vector<Door*>& doors);

  // Answers one request from `sender` (its peer and the channel it came through; nullopt: a sender the door no
  // longer knows): applied once, the same answer when sent again. Any door's thread, one at a time (the gate's
  // service thread calls the doors' answer_requests in turn).
  hapticd_msg_ControlReply answer(const hapticd_msg_ControlRequest& m, const std::optional<Sender>& sender);
  // Ends the claims whose claimant is gone: the channel of its claim closed (a DDS request writer no longer matched
  // - a clean exit deletes it, a vanished participant is removed when its lease runs out -, a connection closed),
  // or no sign of life for claim_hold_s on end, counted from claim_grace_s after the claim (a killed or frozen
  // DDS process stops asserting its command writers' liveliness: the command reader's lease, 0.5 s; a stall
  // shorter than the hold keeps the claim - the engine's forces fade at its command deadline meanwhile).
  void check_claims();

  [[nodiscard]] std::uint64_t claims_ended() const noexcept { return claims_ended_.load(); }
  // Whether the channel of a claim or a stop is gone (its peer left), as its door tells.
  [[nodiscard]] bool gone(const Sender& s) const;
  // Requests refused because their client id or subject is not UTF-8 text.
  [[nodiscard]] std::uint64_t text_refused() const noexcept { return text_refused_.load(); }

 private:
  // A request as its handler sees it.
  struct Request {
    const hapticd_msg_ControlRequest& message;
    const Sender& sender;  // the requester and the channel of its request (a claim ends when it is gone)
    const PeerId& requester;
    std::string_view client;
    std::string_view name;
    std::vector<double> values;
  };
  struct Answer {
    Answer() = default;
    Answer(bool accepted_, std::string message_, std::vector<double> values_ = {})
        : accepted(accepted_), message(std::move(message_)), values(std::move(values_)) {}
    bool accepted = false;
    std::string message;
    std::vector<double> values;  // a get request's value
  };
  Answer dispatch(DeviceGate& d, const Request& r);
  // A group request to the group's devices (every: "*", all the server's devices).
  Answer dispatch_group(const std::vector<DeviceGate*>& members, bool every, const Request& r);
  Answer group_claim(const std::vector<DeviceGate*>& members, const Request& r);
  Answer group_release(const std::vector<DeviceGate*>& members, const Request& r);
  Answer group_stop(const std::vector<DeviceGate*>& members, const Request& r);
  Answer group_recover(const std::vector<DeviceGate*>& members, const Request& r);
  // Whether the requester may drive the device (free, or claimed by the requester's participant); else the
  // refusal names the owner.
  std::optional<Answer> refused_unless_owner(const DeviceGate& d, const Request& r) const;
  // Whether the requester may recover the device (docs/safety.md, "Who may recover a stopped device"): first the
  // requester's own latched E-stops are released; with others' still latched, no; else a stopper, the owner,
  // or anyone on a free device may. nullopt: it may; else the refusal.
  std::optional<Answer> refused_recovery(DeviceGate& d, const Request& r);
  [[nodiscard]] bool alive(const PeerId& p) const;

  // The device's part of a request (session/device_requests), once the bridge has checked the requester.
  Answer forward(DeviceGate& d, DeviceRequest::Kind kind, const Request& r);
  Answer claim(DeviceGate& d, const Request& r);
  Answer release(DeviceGate& d, const Request& r);
  Answer switch_scheme(DeviceGate& d, const Request& r);
  Answer set_parameter(DeviceGate& d, const Request& r);
  Answer get_parameter(DeviceGate& d, const Request& r);
  Answer drive_operator(DeviceGate& d, const Request& r);
  Answer emergency_stop(DeviceGate& d, const Request& r);
  Answer recover(DeviceGate& d, const Request& r);
  Answer describe(DeviceGate& d, const Request& r);

  DeviceGates& devices_;
  EventFanout& events_;
  StateFanout& publisher_;
  std::array<Door*, kDoorKinds> doors_{};  // by DoorKind
  std::int64_t claim_grace_ns_;
  std::int64_t claim_hold_ns_;
  bool tuning_by_anyone_;  // gate.tuning_by: anyone may set a claimed device's tunable parameters (not safety.*)
  std::atomic<std::uint64_t> claims_ended_{0};
  std::atomic<std::uint64_t> text_refused_{0};
  std::unique_ptr<AnsweredRequests> answered_ = std::make_unique<AnsweredRequests>();  // about 90 kB
};

}  // namespace hapticd::server
