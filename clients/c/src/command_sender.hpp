#pragma once
// The C API's engine commands, handed to a thread of their own: Cyclone DDS allocates when it writes a sample
// (a serialised EngineCommand is larger than its pool's 256 bytes), so the caller's thread - a game's physics
// step, the receive thread answering a state - only copies the command into its target's slot (a triple buffer,
// no allocation, no wait) and wakes the sender thread (a futex), which writes the newest command of each target.
// A write that fails is told by the next send to the same target (HAPTICD_ERROR_DDS).
#include <array>
#include <atomic>
#include <cstdint>
#include <string_view>
#include <thread>

#include "hapticd/client/client.hpp"
#include "hapticd/realtime/latest_value.hpp"

namespace hapticd::client_c {

class CommandSender {
 public:
  static constexpr std::size_t kTargets = 16;  // devices and groups a client commands
  explicit CommandSender(client::Client& client);
  ~CommandSender();
  CommandSender(const CommandSender&) = delete;
  CommandSender& operator=(const CommandSender&) = delete;

  enum class Result { handed_over, no_slot, previous_write_failed };
  // Any thread; commands of one target from one thread at a time (others wait a copy's time). Allocation-free.
  Result send(std::string_view device, const client::EngineCommand& command) noexcept;
  Result send_group(std::string_view group, const std::array<client::DeviceCommand, client::kMaxGroupDevices>& list,
                    int count) noexcept;
  // Commands written so far (for tests).
  [[nodiscard]] std::uint64_t written() const noexcept { return written_.load(); }

 private:
  struct Pending {
    client::EngineCommand command;
    std::array<client::DeviceCommand, client::kMaxGroupDevices> group{};
    int count = 0;  // a group command's devices; 0: a device command
  };
  struct Slot {
    std::atomic<int> state{0};  // 0 free, 1 being set up, 2 ready
    client::Name target;
    std::atomic_flag publishing = ATOMIC_FLAG_INIT;  // one publisher at a time (LatestValue has one writer)
    realtime::LatestValue<Pending> value;
    std::atomic<bool> failed{false};
  };
  Slot* slot_for(std::string_view target) noexcept;
  Result hand_over(Slot& slot, const Pending& pending) noexcept;
  void run() noexcept;

  client::Client& client_;
  std::array<Slot, kTargets> slots_;
  std::atomic<std::uint32_t> sequence_{0};  // the futex word: bumped for every command handed over
  std::atomic<bool> stopping_{false};
  std::atomic<std::uint64_t> written_{0};
  std::thread thread_;
};

}  // namespace hapticd::client_c
