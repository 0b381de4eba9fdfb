#pragma once
// The link's delay and the peer's clock, measured from the packets (docs/teleoperation.md, "Measured delay"). No
// common clock is assumed: each packet carries its send time on the sender's clock (t3) and echoes the packet that
// arrived at the sender last - that packet's send time on the receiver's clock (t1) and when it arrived, on the
// sender's (t2) - and the receiver notes its arrival (t4). As in NTP (RFC 5905):
//   round trip = (t4 - t1) - (t3 - t2)        clock offset (peer minus own) = ((t2 - t1) + (t3 - t4)) / 2
// and each packet's one-way delay to this side is t4 - t3 + offset. The offset is taken from the exchanges with the
// shortest round trip in the last `window_s` (the ones least disturbed by queueing and jitter; the mean of those in
// the newest of 16 bins of the window that has it, within 50 us - clocks that tick in a loop's cycles give many), so
// it follows a drifting clock and ignores a late packet. What two clocks cannot tell apart is an asymmetric path: a way
// out slower than the way back reads as an offset of half the difference, and both one-way delays as half the round
// trip each. Real-time safe: fixed storage, no allocation.
#include <array>
#include <cstdint>

namespace hapticd::teleop {

struct LinkClockFigures {
  std::uint64_t samples = 0;  // exchanges taken
  std::uint64_t refused = 0;  // exchanges whose times cannot be (a negative round trip or hold): not taken
  bool valid = false;         // at least one exchange taken
  double round_trip_s = 0.0;  // the shortest round trip in the window
  double offset_s = 0.0;      // the peer's clock minus this side's, from the exchanges that took it
  // The newest packet's one-way delay to this side, and the newest echoed packet's from this side (from its
  // exchange's times and the offset).
  double delay_in_s = 0.0;
  double delay_out_s = 0.0;
  // Their means since the first exchange: of every packet to this side, of every packet of this side's echoed
  // (once each, however many of the peer's packets echo it).
  double mean_delay_in_s = 0.0;
  double mean_delay_out_s = 0.0;
};

class LinkClock {
 public:
  // The shortest round trip is looked for among the exchanges of the last window_s, kept as the shortest of each
  // of kBins bins of window_s / kBins.
  static constexpr int kBins = 16;
  explicit LinkClock(double window_s = 2.0) noexcept;

  // One exchange: t1 the echoed packet's send time (own clock), t2 its arrival at the peer and t3 this packet's
  // send time (the peer's clock), t4 this packet's arrival (own clock) [ns].
  void exchange(std::int64_t t1, std::int64_t t2, std::int64_t t3, std::int64_t t4) noexcept;
  // Forgets the peer's clock (another peer: its clock is another).
  void reset() noexcept;

  [[nodiscard]] const LinkClockFigures& figures() const noexcept { return figures_; }

 private:
  struct Bin {
    std::int64_t start_ns = 0;  // own clock
    bool used = false;
    double round_trip_s = 0.0;  // the bin's shortest
    // The exchanges that took it (within 50 us): the first one's offset and the others' deviations from it, summed.
    double offset_s = 0.0;
    double offset_deviation_s = 0.0;
    std::uint64_t ties = 0;
  };
  std::int64_t bin_ns_;
  std::array<Bin, kBins> bins_{};
  LinkClockFigures figures_;
  double sum_in_ = 0.0, sum_out_ = 0.0;
  std::uint64_t echoed_ = 0;
  std::int64_t last_echo_ = 0;  // the last exchange's t1
};

}  // namespace hapticd::teleop
