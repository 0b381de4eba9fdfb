#include "doors/teleop/teleop_link.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <stdexcept>

#include "executor/loop_clock.hpp"
#include "gate/peer.hpp"
#include "hapticd/dds/conversion.hpp"
#include "hapticd/dds/teleop_validation.hpp"
#include "session/device_requests.hpp"

namespace hapticd::server {
namespace {

void copy(double (&to)[3], const Eigen::Vector3d& from) noexcept {
  for (int i = 0; i < 3; ++i) to[i] = from[i];
}

Eigen::Vector3d vec(const double (&v)[3]) noexcept { return {v[0], v[1], v[2]}; }

// The wire's quaternion is w, x, y, z (checked unit by check_teleop_packet).
Eigen::Quaterniond quat(const double (&q)[4]) noexcept {
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized();
}

void copy(double (&to)[4], const Eigen::Quaterniond& from) noexcept {
  to[0] = from.w();
  to[1] = from.x();
  to[2] = from.y();
  to[3] = from.z();
}

std::int32_t role_of(teleop::Role r) noexcept {
  return r == teleop::Role::master ? hapticd_msg_TELEOP_MASTER : hapticd_msg_TELEOP_REMOTE;
}

// The DDS partition a device's teleoperation packets travel in (DDS Security: granted to its server's identity).
std::string link_partition(const std::string& device) { return "hapticd.teleop." + device; }

// The participant of a matched writer, for messages ("participant 0110a4c3..."; "?" when no longer matched).
std::string participant_of(dds_entity_t reader, dds_instance_handle_t writer) {
  dds_builtintopic_endpoint_t* data = dds_get_matched_publication_data(reader, writer);
  if (data == nullptr) return "?";
  std::array<unsigned char, 16> guid{};
  std::memcpy(guid.data(), data->participant_key.v, guid.size());
  dds_builtintopic_free_endpoint(data);
  return PeerId::dds_participant(guid).text().substr(12);  // the GUID's prefix, without "participant "
}

}  // namespace

TeleopLink::TeleopLink(const TeleoperationSettings& settings, DeviceGate& device, TeleopPhase& phase,
                       const dds::Participant& participant, EventFanout& events, bool real_time)
    : settings_(settings),
      device_(device),
      events_(events),
      name_(settings.device),
      reader_(participant, {}, nullptr, {link_partition(settings.peer)}),
      writer_(participant, {}, link_partition(settings.device)),
      phase_(phase),
      real_time_(real_time) {
  dds::set_text(packet_.sender, name_);
  dds::set_text(packet_.receiver, settings.peer);
  packet_.role = role_of(settings.role);
  if (const int dof = device_.device->description().dof(); settings.link.rotation && dof < 6)
    throw std::runtime_error(fmt::format(
        "teleoperation.rotation: device '{}' has {} joints and cannot render the link's torques (rotation needs a "
        "six-degree-of-freedom handle such as the ViSHaRD6's)",
        name_, dof));
  std::lock_guard lock(device_.mutex);
  device_.gate.claim("teleoperation:" + settings.peer, PeerId::link());
  device_.claimed_ns = 0;
}

std::int64_t TeleopLink::link_now(std::int64_t state_ns) const noexcept {
  return real_time_ ? monotonic_now_ns() - origin_ns_ : state_ns;
}

void TeleopLink::take_packets(std::int64_t state_ns) {
  const std::int32_t peer_role =
      role_of(settings_.role == teleop::Role::master ? teleop::Role::remote : teleop::Role::master);
  reader_.take([&](const hapticd_msg_TeleopPacket& p, const dds_sample_info_t& info) {
    // Packets of other links in the domain are not this link's business; a malformed one for this link is.
    if (dds::terminated(p.receiver) && dds::text_of(p.receiver) != name_) return;
    std::string_view problem = dds::check_teleop_packet(p);
    if (problem.empty() && dds::text_of(p.sender) != settings_.peer) problem = "it comes from another device";
    if (problem.empty() && p.role != peer_role) problem = "its sender has the same role as this side";
    if (!problem.empty()) return reject("teleoperation_packet", problem, rejected_);
    if (!admit(info.publication_handle)) return;
    teleop::LinkPacket packet;
    packet.sequence = p.serial;
    packet.sent_ns = p.sent_ns;
    packet.has_echo = p.has_echo;
    packet.echo_sent_ns = p.echo_sent_ns;
    packet.echo_received_ns = p.echo_received_ns;
    packet.position = vec(p.position);
    packet.velocity = vec(p.velocity);
    packet.force = vec(p.force);
    packet.wave = vec(p.wave);
    packet.energy_in = p.energy_in;
    packet.orientation = quat(p.orientation);
    packet.angular_velocity = vec(p.angular_velocity);
    packet.torque = vec(p.torque);
    packet.rotation_energy_in = p.rotation_energy_in;
    packet.stopped = p.stopped;
    phase_.deliver(packet, link_now(state_ns));
    taken_.fetch_add(1, std::memory_order_relaxed);
  });
}

void TeleopLink::reject(std::string_view code, std::string_view problem, std::atomic<std::uint64_t>& counter) {
  const std::uint64_t n = counter.fetch_add(1, std::memory_order_relaxed) + 1;
  if (&counter != &rejected_) rejected_.fetch_add(1, std::memory_order_relaxed);
  if (n == 1 || n % 1000 == 0) {
    spdlog::warn("{}: a teleoperation packet was rejected: {} ({} so far)", name_, problem, n);
    events_.send(device_, hapticd_msg_EVENT_ENGINE_REJECTED, code,
                 fmt::format("teleoperation packet rejected: {} ({} so far)", problem, n));
  }
}

bool TeleopLink::matched(dds_instance_handle_t writer) const {
  std::array<dds_instance_handle_t, 64> writers{};  // the peer's and a few more: an impostor is one writer too
  const dds_return_t n = dds_get_matched_publications(reader_.get(), writers.data(), writers.size());
  if (n < 0) return true;  // unknown: the binding stays
  const std::size_t shown = std::min<std::size_t>(static_cast<std::size_t>(n), writers.size());
  if (std::find(writers.begin(), writers.begin() + static_cast<std::ptrdiff_t>(shown), writer) !=
      writers.begin() + static_cast<std::ptrdiff_t>(shown))
    return true;
  return static_cast<std::size_t>(n) > writers.size();  // more than shown: it may be among the rest
}

bool TeleopLink::admit(dds_instance_handle_t writer) {
  if (writer == bound_) return true;
  if (bound_ != 0 && matched(bound_)) {
    // The participants are looked up (discovery data, allocated) only for the packets reported: the first and
    // every 1000th of a flood.
    const std::uint64_t next = impostors_.load(std::memory_order_relaxed) + 1;
    const bool reported = next == 1 || next % 1000 == 0;
    reject("teleoperation_impostor",
           reported ? "it comes from participant " + participant_of(reader_.get(), writer) +
                          ", not from the peer the link is bound to (participant " +
                          participant_of(reader_.get(), bound_) + ")"
                    : std::string(),
           impostors_);
    return false;
  }
  const bool again = bound_ != 0;
  bound_ = writer;
  bindings_.fetch_add(1, std::memory_order_relaxed);
  const std::string who = participant_of(reader_.get(), writer);
  if (!again) {
    spdlog::info("{}: teleoperation link bound to '{}' (participant {})", name_, settings_.peer, who);
    return true;
  }
  phase_.peer_changed();  // a restarted peer: its serials and energy start afresh
  const std::string message = fmt::format(
      "teleoperation link re-bound to '{}' (participant {}): the peer it was bound to is gone", settings_.peer, who);
  spdlog::warn("{}: {}", name_, message);
  events_.send(device_, hapticd_msg_EVENT_ENGINE_STALE, "teleoperation_rebound", message);
  return true;
}

void TeleopLink::stopped(teleop::PortStop stop, const std::string& message) {
  const std::string_view code = teleop::stop_code(stop);
  stops_.fetch_add(1, std::memory_order_relaxed);
  spdlog::warn("{}: {}", name_, message);
  events_.send(device_, hapticd_msg_EVENT_ESTOP, code, message);
}

TeleopLink::Energy TeleopLink::energy() const noexcept {
  return {in_.load(std::memory_order_relaxed),
          out_.load(std::memory_order_relaxed),
          dissipated_.load(std::memory_order_relaxed),
          lowest_observed_.load(std::memory_order_relaxed),
          max_force_.load(std::memory_order_relaxed),
          peer_claimed_.load(std::memory_order_relaxed),
          peer_credited_.load(std::memory_order_relaxed),
          max_torque_.load(std::memory_order_relaxed)};
}

TeleopLink::Delay TeleopLink::delay() const noexcept {
  return {delay_valid_.load(std::memory_order_relaxed),  round_trip_.load(std::memory_order_relaxed),
          offset_.load(std::memory_order_relaxed),       mean_in_.load(std::memory_order_relaxed),
          mean_out_.load(std::memory_order_relaxed),     delay_samples_.load(std::memory_order_relaxed),
          delay_refused_.load(std::memory_order_relaxed)};
}

void TeleopLink::on_state(const DeviceSnapshot& s) {
  // The link's clock. Real time: the monotonic clock read when each packet has been taken and when this side's is
  // written (the link's delay is their transit, not how late this thread or the loop runs), from the first state's
  // time. So a reading can only be late - an arrival read after the take, a send read before the write - which
  // lengthens the round trips it enters, and the clock estimate's shortest round trip leaves those out. (Stamps
  // read early shorten round trips, which the estimate then picks: the state's time plus what had passed since its
  // cycle was due read early by the time between the loop's wake-up and the device's read - CI read a one-way delay
  // 2.4 ms long.) Virtual: the state's time (the loop's packets carry their cycle's).
  if (real_time_ && !started_) origin_ns_ = monotonic_now_ns() - s.time_ns;
  started_ = true;
  take_packets(s.time_ns);

  // The newest packet the loop made (its port runs in the device's cycle: session/teleop_phase.hpp), sent now.
  teleop::LinkPacket out;
  if (phase_.take_outgoing(out)) {
    packet_.serial = out.sequence;
    packet_.has_echo = out.has_echo;
    packet_.echo_sent_ns = out.echo_sent_ns;
    packet_.echo_received_ns = out.echo_received_ns;
    copy(packet_.position, out.position);
    copy(packet_.velocity, out.velocity);
    copy(packet_.force, out.force);
    copy(packet_.wave, out.wave);
    packet_.energy_in = out.energy_in;
    copy(packet_.orientation, out.orientation);
    copy(packet_.angular_velocity, out.angular_velocity);
    copy(packet_.torque, out.torque);
    packet_.rotation_energy_in = out.rotation_energy_in;
    packet_.stopped = out.stopped;
    packet_.sent_ns = real_time_ ? link_now(s.time_ns) : out.sent_ns;
    if (writer_.write(packet_)) sent_.fetch_add(1, std::memory_order_relaxed);
  }
  report();
}

void TeleopLink::report() {
  TeleopReport r;
  if (!phase_.take_report(r)) return;
  const TeleopReport& seen = seen_;
  // What the loop's port decided - a stop, a loss, the link back, the wait for the peer - said once each.
  if (r.waiting && !seen.waiting)
    spdlog::info("{}: no teleoperation packet from '{}' yet: waiting for the peer (this side holds still)", name_,
                 settings_.peer);
  auto silent = [&] { return fmt::format("no packet from '{}' for {:.2f} s", settings_.peer, r.silence_s); };
  if (r.lost_stops > seen.lost_stops)
    stopped(teleop::PortStop::link_lost, "teleoperation link lost (" + silent() + "): the remote stops");
  if (r.peer_stops > seen.peer_stops)
    stopped(teleop::PortStop::peer_stopped,
            "teleoperation: the peer device '" + settings_.peer + "' stopped; this one stops too");
  if (r.losses > seen.losses && r.lost_stops == seen.lost_stops) {
    const std::string message = "teleoperation link lost (" + silent() + "): the force fades out";
    spdlog::warn("{}: {}", name_, message);
    events_.send(device_, hapticd_msg_EVENT_ENGINE_STALE, "teleoperation_link_lost", message);
  }
  if (r.backs > seen.backs) {
    spdlog::info("{}: teleoperation link back: packets from '{}' again", name_, settings_.peer);
    events_.send(device_, hapticd_msg_EVENT_ENGINE_STALE, "teleoperation_link_back",
                 "teleoperation link back: packets from '" + settings_.peer + "' again");
  }
  if (r.dropped > seen.dropped && (seen.dropped == 0 || r.dropped / 1000 > seen.dropped / 1000))
    spdlog::warn("{}: {} teleoperation packets dropped so far: the loop had not taken the 256 before them", name_,
                 r.dropped);
  seen_ = r;
  losses_.store(r.losses, std::memory_order_relaxed);

  in_.store(r.energy_in, std::memory_order_relaxed);
  out_.store(r.energy_out, std::memory_order_relaxed);
  dissipated_.store(r.dissipated, std::memory_order_relaxed);
  peer_claimed_.store(r.peer_claimed, std::memory_order_relaxed);
  peer_credited_.store(r.peer_credited, std::memory_order_relaxed);
  lowest_observed_.store(r.lowest_observed, std::memory_order_relaxed);
  max_force_.store(r.max_force, std::memory_order_relaxed);
  max_torque_.store(r.max_torque, std::memory_order_relaxed);
  const teleop::LinkClockFigures& clock = r.clock;
  delay_valid_.store(clock.valid, std::memory_order_relaxed);
  round_trip_.store(clock.round_trip_s, std::memory_order_relaxed);
  offset_.store(clock.offset_s, std::memory_order_relaxed);
  mean_in_.store(clock.mean_delay_in_s, std::memory_order_relaxed);
  mean_out_.store(clock.mean_delay_out_s, std::memory_order_relaxed);
  delay_samples_.store(clock.samples, std::memory_order_relaxed);
  delay_refused_.store(clock.refused, std::memory_order_relaxed);
}

}  // namespace hapticd::server
