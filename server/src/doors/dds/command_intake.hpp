#pragma once
// The DDS door's command path, on Cyclone's receive threads (a listener: no thread wake-up between a command's
// arrival and its hand-over to the loop): who wrote it (PeerDirectory: the writer's participant is the peer, the
// writer the channel), then the gate (Gate::admit: owner, order, freshness, content; the hand-over to the loop).
// Command writers' liveliness changes go to the PeerDirectory and wake the gate's service thread, which checks
// the claims; the request reader's new samples wake it too.
#include <atomic>
#include <memory>
#include <mutex>
#include <vector>

#include "doors/dds/dds_endpoints.hpp"
#include "gate/gate.hpp"

namespace hapticd::server {

class CommandIntake {
 public:
  CommandIntake(DdsEndpoints& dds, Gate& gate);
  // Attaches the listeners to the command and request readers; from then on commands flow. Last, once
  // everything is built.
  void listen();
  // Detaches them: no more commands (idempotent).
  void close();
  // The DDS deadlines the devices' engines missed (the service thread counts them: count_deadline_misses).
  void count_deadline_misses();
  [[nodiscard]] std::uint64_t deadline_misses(std::size_t device) const { return deadline_misses_[device].load(); }

 private:
  void take_commands();
  // A group's commands (one GroupCommand per cycle from the engine that claimed the group): each part as a
  // device's command.
  void take_group_commands();
  Sender sender_of(dds_entity_t reader, const dds_sample_info_t& info);
  void liveliness_changed(const dds_liveliness_changed_status_t& status);

  DdsEndpoints& dds_;
  Gate& gate_;
  std::mutex take_mutex_;  // one take at a time: local writers deliver on their own threads, buffers are shared
  // Per device: its instance on the command reader (deadline misses are per instance), and the misses.
  std::unique_ptr<std::atomic<dds_instance_handle_t>[]> instances_;
  std::unique_ptr<std::atomic<std::uint64_t>[]> deadline_misses_;
};

}  // namespace hapticd::server
