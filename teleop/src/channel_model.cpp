#include "hapticd/teleop/channel_model.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace hapticd::teleop {
namespace {

bool later(const auto& a, const auto& b) {
  return a.arrival_ns != b.arrival_ns ? a.arrival_ns > b.arrival_ns : a.order > b.order;
}

}  // namespace

std::string channel_settings_problem(const ChannelSettings& s) {
  const auto bad = [](double v, double lo, double hi) { return !std::isfinite(v) || v < lo || v > hi; };
  if (bad(s.delay_s, 0.0, 10.0)) return "delay_s must be in [0, 10] s";
  if (bad(s.delay_variation_s, 0.0, s.delay_s)) return "delay_variation_s must be in [0, delay_s]";
  if (bad(s.variation_period_s, 1e-3, 3600.0)) return "variation_period_s must be in [0.001, 3600] s";
  if (bad(s.jitter_s, 0.0, 10.0)) return "jitter_s must be in [0, 10] s";
  if (bad(s.loss, 0.0, 0.999)) return "loss must be in [0, 0.999]";
  return "";
}

ChannelModel::ChannelModel(const ChannelSettings& settings)
    : settings_(settings), state_(settings.seed ^ 0x7E1E0F5EEDULL) {
  if (const std::string problem = channel_settings_problem(settings); !problem.empty())
    throw std::invalid_argument("channel: " + problem);
  flight_.reserve(kCapacity);
}

double ChannelModel::uniform() noexcept {
  // splitmix64: the same numbers on every platform and library (std's distributions are not specified exactly).
  std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}

void ChannelModel::send(const LinkPacket& packet, std::int64_t now_ns) noexcept {
  ++counters_.sent;
  // Both draws happen for every packet, lost or not, so that a setting changes only what it governs.
  const bool lost = uniform() < settings_.loss;
  const double jitter = uniform() * settings_.jitter_s;
  if (lost) {
    ++counters_.lost;
    return;
  }
  if (flight_.size() >= kCapacity) {
    ++counters_.overflowed;
    return;
  }
  const double t = static_cast<double>(now_ns) * 1e-9;
  const double delay = settings_.delay_s +
                       settings_.delay_variation_s * std::sin(2.0 * M_PI * t / settings_.variation_period_s) + jitter;
  flight_.push_back({now_ns + std::llround(std::max(0.0, delay) * 1e9), order_++, packet});
  std::push_heap(flight_.begin(), flight_.end(), [](const InFlight& a, const InFlight& b) { return later(a, b); });
}

LinkPacket ChannelModel::pop() noexcept {
  std::pop_heap(flight_.begin(), flight_.end(), [](const InFlight& a, const InFlight& b) { return later(a, b); });
  const LinkPacket p = flight_.back().packet;
  flight_.pop_back();
  return p;
}

}  // namespace hapticd::teleop
