#pragma once
// The bridge's requests, on its receiver thread: each request is answered by the handler of its kind (claim,
// release, switch scheme, set parameter, operator, E-stop, recover, describe; for a device group: claim all or
// none, release, E-stop, recover all or none). The requester is the participant
// of the request's writer, whatever client id the request declares; owner-only requests (release, switch, set)
// are accepted only from the claimant's participant, or on a free device; anyone may stop a device, and a stop
// latches until its requester recovers it (StopLatches); a fault without a latched stop is recovered by the owner
// (or anyone on a free device). A request sent again (the same
// client and request id from the same participant) is answered again and not applied twice (AnsweredRequests). The same
// thread ends claims whose claimant's participant is gone, and counts the engines' missed deadlines.
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bridge/answered_requests.hpp"
#include "bridge/dds_endpoints.hpp"
#include "bridge/device_link.hpp"
#include "bridge/event_sender.hpp"
#include "bridge/state_publisher.hpp"
#include "session/device_requests.hpp"

namespace hapticd::server {

class RequestDispatcher {
 public:
  RequestDispatcher(DdsEndpoints& dds, DeviceLinks& links, EventSender& events, StatePublisher& publisher,
                    double claim_grace_s, double claim_hold_s);

  // Answers every request waiting on the reader.
  void handle_requests();
  // Answers one request from `requester` (nullopt: a writer no longer known) through `writer` (a DDS request
  // writer, or an engine socket's client: socket_writer()): applied once, the same answer when sent again.
  hapticd_msg_ControlReply answer(const hapticd_msg_ControlRequest& m, const std::optional<PeerId>& requester,
                                  dds_instance_handle_t writer);
  // Ends the claims whose claimant is gone: its request writer no longer matched (a clean exit deletes it; a
  // vanished participant is removed when its lease runs out), or no command writer of its participant whose
  // liveliness holds for claim_hold_s on end, counted from claim_grace_s after the claim (a killed or frozen
  // process stops asserting it: the command reader's lease, 0.5 s; a stall shorter than the hold keeps the
  // claim - the engine's forces fade at its command deadline meanwhile).
  void check_claims();
  // Counts the DDS deadlines the devices' engines missed.
  void check_engine_deadlines();

  [[nodiscard]] std::uint64_t claims_ended() const noexcept { return claims_ended_.load(); }
  // Requests refused because their client id or subject is not UTF-8 text.
  [[nodiscard]] std::uint64_t text_refused() const noexcept { return text_refused_.load(); }

 private:
  // A request as its handler sees it.
  struct Request {
    const hapticd_msg_ControlRequest& message;
    dds_instance_handle_t writer;  // the request's writer (a claim ends when it is gone)
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
  Answer dispatch(DeviceLink& d, const Request& r);
  // A group request to the group's devices (every: "*", all the server's devices).
  Answer dispatch_group(const std::vector<DeviceLink*>& members, bool every, const Request& r);
  Answer group_claim(const std::vector<DeviceLink*>& members, const Request& r);
  Answer group_release(const std::vector<DeviceLink*>& members, const Request& r);
  Answer group_stop(const std::vector<DeviceLink*>& members, const Request& r);
  Answer group_recover(const std::vector<DeviceLink*>& members, const Request& r);
  // Whether the requester may drive the device (free, or claimed by the requester's participant); else the
  // refusal names the owner.
  std::optional<Answer> refused_unless_owner(const DeviceLink& d, const Request& r) const;
  // Whether the requester may recover the device (docs/safety.md, "Who may recover a stopped device"): first the
  // requester's own latched E-stops are released; with others' still latched, no; else a stopper, the owner,
  // or anyone on a free device may. nullopt: it may; else the refusal.
  std::optional<Answer> refused_recovery(DeviceLink& d, const Request& r);
  // Whether the participant of a stop's request writer has left the domain.
  [[nodiscard]] bool writer_gone(dds_instance_handle_t writer) const;

  // The device's part of a request (session/device_requests), once the bridge has checked the requester.
  Answer forward(DeviceLink& d, DeviceRequest::Kind kind, const Request& r);
  Answer claim(DeviceLink& d, const Request& r);
  Answer release(DeviceLink& d, const Request& r);
  Answer switch_scheme(DeviceLink& d, const Request& r);
  Answer set_parameter(DeviceLink& d, const Request& r);
  Answer get_parameter(DeviceLink& d, const Request& r);
  Answer drive_operator(DeviceLink& d, const Request& r);
  Answer emergency_stop(DeviceLink& d, const Request& r);
  Answer recover(DeviceLink& d, const Request& r);
  Answer describe(DeviceLink& d, const Request& r);

  DdsEndpoints& dds_;
  DeviceLinks& links_;
  EventSender& events_;
  StatePublisher& publisher_;
  std::int64_t claim_grace_ns_;
  std::int64_t claim_hold_ns_;
  std::atomic<std::uint64_t> claims_ended_{0};
  std::atomic<std::uint64_t> text_refused_{0};
  std::unique_ptr<AnsweredRequests> answered_ = std::make_unique<AnsweredRequests>();  // about 90 kB
};

}  // namespace hapticd::server
