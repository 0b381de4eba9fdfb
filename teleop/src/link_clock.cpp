#include "hapticd/teleop/link_clock.hpp"

#include <algorithm>
#include <cmath>

namespace hapticd::teleop {
namespace {

// Differences of any two clock readings exactly (a peer's clock may read anything: no overflow).
double seconds(__int128 ns) noexcept { return static_cast<double>(ns) * 1e-9; }

std::int64_t floor_div(std::int64_t a, std::int64_t b) noexcept {
  const std::int64_t q = a / b;
  return (a % b != 0 && (a < 0) != (b < 0)) ? q - 1 : q;
}

constexpr double kLongestRoundTrip = 600.0;  // [s]: an echo older than this is not an exchange of this link

}  // namespace

LinkClock::LinkClock(double window_s) noexcept
    : bin_ns_(std::max<std::int64_t>(1, std::llround(std::clamp(window_s, 1e-3, 3600.0) * 1e9 / kBins))) {}

void LinkClock::reset() noexcept {
  bins_ = {};
  figures_ = LinkClockFigures{};
  sum_in_ = sum_out_ = 0.0;
  echoed_ = 0;
  last_echo_ = 0;
}

void LinkClock::exchange(std::int64_t t1, std::int64_t t2, std::int64_t t3, std::int64_t t4) noexcept {
  const __int128 away = static_cast<__int128>(t4) - t1;  // own clock: from the echoed packet's send to now
  const __int128 held = static_cast<__int128>(t3) - t2;  // the peer's clock: from its arrival to this send
  const __int128 round_trip = away - held;
  if (away < 0 || held < 0 || round_trip < 0 || seconds(away) > kLongestRoundTrip) {
    ++figures_.refused;
    return;
  }
  const double offset = 0.5 * seconds((static_cast<__int128>(t2) - t1) + (static_cast<__int128>(t3) - t4));
  const double rtt = seconds(round_trip);

  const std::int64_t slot = floor_div(t4, bin_ns_);
  Bin& bin = bins_[static_cast<std::size_t>(((slot % kBins) + kBins) % kBins)];
  const std::int64_t start = slot * bin_ns_;
  if (!bin.used || bin.start_ns != start) bin = Bin{start, true, rtt, offset};
  if (rtt < bin.round_trip_s) {
    bin.round_trip_s = rtt;
    bin.offset_s = offset;
  }
  // The shortest round trip among the bins of the window (the present bin and the kBins - 1 before it).
  const Bin* best = &bin;
  for (const Bin& b : bins_)
    if (b.used && b.start_ns <= start && start - b.start_ns < kBins * bin_ns_ && b.round_trip_s < best->round_trip_s)
      best = &b;

  LinkClockFigures& f = figures_;
  ++f.samples;
  f.valid = true;
  f.round_trip_s = best->round_trip_s;
  f.offset_s = best->offset_s;
  f.delay_in_s = seconds(static_cast<__int128>(t4) - t3) + f.offset_s;
  f.delay_out_s = seconds(static_cast<__int128>(t2) - t1) - f.offset_s;
  sum_in_ += f.delay_in_s;
  f.mean_delay_in_s = sum_in_ / static_cast<double>(f.samples);
  if (echoed_ == 0 || t1 != last_echo_) {
    sum_out_ += f.delay_out_s;
    ++echoed_;
    last_echo_ = t1;
  }
  f.mean_delay_out_s = sum_out_ / static_cast<double>(echoed_);
}

}  // namespace hapticd::teleop
