#include "command_sender.hpp"

#include "hapticd/realtime/tick_signal.hpp"

namespace hapticd::client_c {

CommandSender::CommandSender(client::Client& client) : client_(client) {
  thread_ = std::thread([this] { run(); });
}

CommandSender::~CommandSender() {
  stopping_.store(true);
  sequence_.fetch_add(1);
  realtime::TickSignal::wake(sequence_);
  if (thread_.joinable()) thread_.join();
}

CommandSender::Slot* CommandSender::slot_for(std::string_view target) noexcept {
  for (Slot& s : slots_)
    if (s.state.load(std::memory_order_acquire) == 2 && s.target == target) return &s;
  for (Slot& s : slots_) {
    int expected = 0;
    if (s.state.compare_exchange_strong(expected, 1, std::memory_order_acq_rel)) {
      s.target.assign(target);
      s.state.store(2, std::memory_order_release);
      return &s;
    }
  }
  // A slot another thread set up for the same target meanwhile.
  for (Slot& s : slots_)
    if (s.state.load(std::memory_order_acquire) == 2 && s.target == target) return &s;
  return nullptr;
}

CommandSender::Result CommandSender::hand_over(Slot& slot, const Pending& pending) noexcept {
  while (slot.publishing.test_and_set(std::memory_order_acquire)) {
  }
  slot.value.publish(pending);
  slot.publishing.clear(std::memory_order_release);
  sequence_.fetch_add(1, std::memory_order_release);
  realtime::TickSignal::wake(sequence_);
  return slot.failed.exchange(false) ? Result::previous_write_failed : Result::handed_over;
}

CommandSender::Result CommandSender::send(std::string_view device, const client::EngineCommand& command) noexcept {
  Slot* slot = slot_for(device);
  if (slot == nullptr) return Result::no_slot;
  Pending p;
  p.command = command;
  return hand_over(*slot, p);
}

CommandSender::Result CommandSender::send_group(std::string_view group,
                                                const std::array<client::DeviceCommand, client::kMaxGroupDevices>& list,
                                                int count) noexcept {
  Slot* slot = slot_for(group);
  if (slot == nullptr) return Result::no_slot;
  Pending p;
  p.group = list;
  p.count = count;
  return hand_over(*slot, p);
}

void CommandSender::run() noexcept {
  std::uint32_t seen = 0;
  Pending p;
  while (!stopping_.load()) {
    // Woken by a send; at most 100 ms between looks (the stop, a wake-up lost to a race).
    (void)realtime::TickSignal::wait_while(sequence_, seen, realtime::TickSignal::now_ns() + 100'000'000);
    seen = sequence_.load(std::memory_order_acquire);
    for (Slot& s : slots_) {
      if (s.state.load(std::memory_order_acquire) != 2 || !s.value.take(p)) continue;
      bool ok = false;
      try {
        ok = p.count > 0 ? client_.send_group(s.target.view(), std::span<const client::DeviceCommand>(
                                                                   p.group.data(), static_cast<std::size_t>(p.count)))
                         : client_.send(s.target.view(), p.command);
      } catch (...) {
        ok = false;
      }
      if (ok)
        written_.fetch_add(1);
      else
        s.failed.store(true);
    }
  }
}

}  // namespace hapticd::client_c
