#pragma once
// Which engine commands a device accepts: well-formed, finite and bounded content (dds/command_validation),
// from the device's owner (one engine claims a device at a time; others may observe), in order (serial
// numbers strictly increase; a new claim restarts them), and fresh by the sample's source timestamp.
// Rejected commands are counted per reason and never reach the loop. Used by the DDS bridge's receive thread
// only (not thread-safe).
#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "hapticd/dds/command_validation.hpp"

namespace hapticd::server {

class CommandGate {
 public:
  CommandGate(dds::CommandBounds bounds, double max_sample_age_s) : bounds_(bounds), max_age_ns_(static_cast<std::int64_t>(max_sample_age_s * 1e9)) {}

  // true when `client` now owns the device (it was free or already `client`'s).
  bool claim(std::string_view client);
  // true when `client` owned the device and released it.
  bool release(std::string_view client);
  void release_any() { owner_.clear(); }
  [[nodiscard]] const std::string& owner() const noexcept { return owner_; }

  struct Verdict {
    bool accepted = false;
    dds::RejectReason reason = dds::RejectReason::other;
  };
  // source_ns: the sample's source timestamp, now_ns: the receiving wall clock (both ns since the epoch).
  Verdict admit(const hapticd_msg_EngineCommand& command, std::int64_t source_ns, std::int64_t now_ns);

  [[nodiscard]] std::uint64_t received() const noexcept { return received_; }
  [[nodiscard]] std::uint64_t accepted() const noexcept { return accepted_; }
  [[nodiscard]] const std::array<std::uint64_t, dds::kRejectReasons>& rejected() const noexcept { return rejected_; }
  [[nodiscard]] std::uint64_t rejected_total() const noexcept;

 private:
  Verdict reject(dds::RejectReason reason);

  dds::CommandBounds bounds_;
  std::int64_t max_age_ns_;
  std::string owner_;
  std::uint64_t last_serial_ = 0;
  std::uint64_t received_ = 0, accepted_ = 0;
  std::array<std::uint64_t, dds::kRejectReasons> rejected_{};
};

}  // namespace hapticd::server
