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
constexpr double kTie = 50e-6;               // [s]: round trips this close to the shortest are as short

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
  if (!bin.used || bin.start_ns != start || rtt < bin.round_trip_s - kTie) bin = Bin{start, true, rtt, offset, 0.0, 0};
  if (rtt <= bin.round_trip_s + kTie) {
    bin.offset_deviation_s += offset - bin.offset_s;
    ++bin.ties;
  }
  // The shortest round trip among the bins of the window (the present bin and the kBins - 1 before it), and the
  // mean offset of the exchanges that took it in the newest bin that has it (clocks that tick in steps - a loop's
  // cycles - give many; the newest follows a drifting clock).
  auto in_window = [&](const Bin& b) { return b.used && b.start_ns <= start && start - b.start_ns < kBins * bin_ns_; };
  double shortest = bin.round_trip_s;
  for (const Bin& b : bins_)
    if (in_window(b)) shortest = std::min(shortest, b.round_trip_s);
  const Bin* best = nullptr;
  for (const Bin& b : bins_)
    if (in_window(b) && b.round_trip_s <= shortest + kTie && (best == nullptr || b.start_ns > best->start_ns))
      best = &b;

  LinkClockFigures& f = figures_;
  ++f.samples;
  f.valid = true;
  f.round_trip_s = shortest;
  f.offset_s = best->offset_s + best->offset_deviation_s / static_cast<double>(best->ties);
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
