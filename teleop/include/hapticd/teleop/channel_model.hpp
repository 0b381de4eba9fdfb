#pragma once
// A network in a box for lockstep runs (docs/teleoperation.md, "The channel"): one direction of a link with a
// constant delay, a slow sinusoidal variation of it, per-packet jitter (packets overtake each other: reordering),
// and random loss, all drawn from a seeded generator so that the same seed gives the same run. Real-time safe
// after construction: a fixed-capacity heap of packets in flight (a packet that does not fit is counted and
// dropped, as a full socket buffer would).
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "hapticd/teleop/link_packet.hpp"

namespace hapticd::teleop {

struct ChannelSettings {
  double delay_s = 0.0;             // one-way delay [s]
  double delay_variation_s = 0.0;   // amplitude of a sinusoidal variation of the delay [s], at most delay_s
  double variation_period_s = 2.0;  // its period [s]
  double jitter_s = 0.0;            // each packet's extra delay, uniform in [0, jitter_s] [s]
  double loss = 0.0;                // probability that a packet is lost, in [0, 1)
  std::uint64_t seed = 1;
};

// The settings' first problem ("" when there is none).
std::string channel_settings_problem(const ChannelSettings& settings);

struct ChannelCounters {
  std::uint64_t sent = 0, lost = 0, delivered = 0, overflowed = 0;
  std::uint64_t reordered = 0;  // delivered after a packet sent later
};

class ChannelModel {
 public:
  static constexpr std::size_t kCapacity = 8192;  // packets in flight: 4 s at 2 kHz

  // Throws std::invalid_argument with channel_settings_problem().
  explicit ChannelModel(const ChannelSettings& settings);

  // A packet sent at now_ns; it arrives at now_ns + the delay then, or never.
  void send(const LinkPacket& packet, std::int64_t now_ns) noexcept;

  // Hands every packet that has arrived by now_ns to `receive`, in the order of arrival.
  template <class Receive>
  void deliver(std::int64_t now_ns, Receive&& receive) noexcept {
    while (!flight_.empty() && flight_.front().arrival_ns <= now_ns) {
      const LinkPacket p = pop();
      if (p.sequence < newest_delivered_) {
        ++counters_.reordered;
      } else {
        newest_delivered_ = p.sequence;
      }
      ++counters_.delivered;
      receive(p);
    }
  }

  [[nodiscard]] const ChannelCounters& counters() const noexcept { return counters_; }
  [[nodiscard]] std::size_t in_flight() const noexcept { return flight_.size(); }

 private:
  struct InFlight {
    std::int64_t arrival_ns;
    std::uint64_t order;  // ties: the order sent
    LinkPacket packet;
  };
  LinkPacket pop() noexcept;
  double uniform() noexcept;  // [0, 1)

  ChannelSettings settings_;
  std::uint64_t state_;
  std::uint64_t order_ = 0;
  std::uint64_t newest_delivered_ = 0;
  std::vector<InFlight> flight_;  // a heap, earliest arrival at the front; its capacity reserved up front
  ChannelCounters counters_;
};

}  // namespace hapticd::teleop
