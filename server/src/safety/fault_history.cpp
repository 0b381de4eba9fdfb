#include "safety/fault_history.hpp"

#include <algorithm>

namespace hapticd::server {

void FaultHistory::configure(std::uint32_t cycles, int dof) {
  capacity_ = std::clamp<std::uint32_t>(cycles, 1, kMaxHistoryCycles);
  for (HistoryRecord& r : ring_) {
    r.position.setZero(dof);
    r.velocity.setZero(dof);
    r.torque.setZero(dof);
  }
  next_ = size_ = 0;
}

void FaultHistory::record(const HistoryRecord& r) noexcept {
  ring_[next_] = r;
  next_ = (next_ + 1) % capacity_;
  size_ = std::min(size_ + 1, capacity_);
}

void FaultHistory::copy_to(FaultReport& report) const noexcept {
  report.count = size_;
  const std::uint32_t first = (next_ + capacity_ - size_) % capacity_;
  for (std::uint32_t k = 0; k < size_; ++k) report.records[k] = ring_[(first + k) % capacity_];
}

}  // namespace hapticd::server
