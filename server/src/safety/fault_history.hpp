#pragma once
// The last cycles of a device's state, kept by the loop in a fixed ring, copied into a FaultReport when a fault
// is raised (the report is what the fault event carries: what the device did just before). Fixed-size: recording
// and copying never allocate.
#include <Eigen/Core>
#include <array>
#include <cstdint>

#include "hapticd/joint_vector.hpp"
#include "hapticd/state_flags.hpp"
#include "safety/device_fault.hpp"
#include "safety/safety_settings.hpp"

namespace hapticd::server {

struct HistoryRecord {
  std::uint64_t cycle = 0;
  std::int64_t time_ns = 0;
  JointVector position, velocity, torque;  // torque: what was written
  Eigen::Vector3d handle_position = Eigen::Vector3d::Zero();
  Eigen::Vector3d handle_velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d operator_force = Eigen::Vector3d::Zero();
  Eigen::Vector3d environment_force = Eigen::Vector3d::Zero();
  std::uint32_t flags = 0;  // the safety layer's state flags of the cycle (hapticd/state_flags.hpp)
};

struct FaultReport {
  DeviceFault fault = DeviceFault::none;
  std::uint64_t serial = 0;  // one per fault of this device
  std::uint64_t cycle = 0;
  std::int64_t time_ns = 0;
  std::uint32_t count = 0;        // valid records, oldest first; the last is the cycle before the fault
  std::array<char, 96> reason{};  // the device's reason (Outcome::reason), cut to fit; empty if none
  std::array<HistoryRecord, kMaxHistoryCycles> records;
};

class FaultHistory {
 public:
  void configure(std::uint32_t cycles, int dof);
  void record(const HistoryRecord& r) noexcept;
  // Copies the kept cycles, oldest first.
  void copy_to(FaultReport& report) const noexcept;
  void clear() noexcept { size_ = 0; }

 private:
  std::array<HistoryRecord, kMaxHistoryCycles> ring_;
  std::uint32_t capacity_ = kMaxHistoryCycles;
  std::uint32_t next_ = 0;
  std::uint32_t size_ = 0;
};

}  // namespace hapticd::server
