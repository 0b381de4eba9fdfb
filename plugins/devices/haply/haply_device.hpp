#pragma once
// Haply's Inverse3 (with a VerseGrip) through Haply's Inverse Service ("haply", docs/devices.md): a local service
// that speaks JSON over a WebSocket (the simulation channel, ws://127.0.0.1:10001 by default) and answers each
// message with one state message. A handle device (hapticd/handle.hpp) whose service paces the exchange: an I/O
// thread sends the force at the session's rate, receives the state that answers it, hands it to the loop and ticks
// the device's clock (`server.clock: device`).
//   configure: connect, read the service's inventory, pick the Inverse3 (`device_id`, else the first) and a
//              VerseGrip (`grip`), refuse one that is not ready or not calibrated with the service's word.
//   enable:    the I/O thread starts (its first message registers the session's profile, as Haply's clients do);
//              the first state awaited (1 s).
//   read:      the newest state (a state older than `max_sample_age_s`, a connection that failed, a message that
//              is not the service's: a fault that says so).
//   write:     the force for the next message. On the device's clock the I/O thread waits for the loop's force of
//              its tick (bounded: `command_wait_us`); a late one is held for `hold_ticks` ticks, then zero is sent.
//   disable:   zero force sent, the connection closed.
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>

#include "hapticd/device.hpp"
#include "hapticd/json_reader.hpp"
#include "inverse_service_client.hpp"
#include "servo_handoff.hpp"

namespace hapticd::plugins::haply {

// One state of the service, for the loop.
struct HaplySample {
  std::int64_t received_ns = 0;  // CLOCK_MONOTONIC
  std::array<double, 3> position{}, velocity{};
  std::array<double, 4> orientation{1, 0, 0, 0};  // the grip's, w x y z
  std::uint32_t buttons = 0;
  const char* error = nullptr;  // the connection failed or the message was not the service's (static text)
};

struct HaplyCommand {
  std::array<double, 3> force_n{};
};

class HaplyDevice final : public Device {
 public:
  // The longest device id taken from the service (it is written into every command).
  static constexpr std::size_t kMaxIdLength = 64;
  static ParameterSchema parameter_schema();

  ~HaplyDevice() override;
  void configure(const Parameters& parameters, const PluginContext& context) override;
  [[nodiscard]] const DeviceDescription& description() const override { return description_; }
  Outcome enable() override;
  Outcome read(const CycleTime& cycle, DeviceState& state) override;
  Outcome write_handle(const CycleTime& cycle, const HandleCommand& command) override;
  void disable() override;
  DeviceClock* clock() noexcept override { return handoff_.clock(); }

 private:
  void run() noexcept;  // the I/O thread
  bool take_state(std::string_view text, HaplySample& sample) noexcept;
  void stop() noexcept;

  std::unique_ptr<InverseServiceClient> client_;
  JsonReader json_;
  std::string device_id_, grip_id_;
  std::string grip_kind_;   // "wireless_verse_grip" or "verse_grip"
  double timeout_s_ = 2.0;  // connect_timeout_s: every exchange with the service
  DeviceDescription description_;

  ServoHandoff<HaplySample, HaplyCommand> handoff_;
  std::thread io_;
  std::atomic<bool> running_{false};
  std::atomic<bool> io_done_{true};
  HaplySample sample_;
  bool have_sample_ = false;
};

}  // namespace hapticd::plugins::haply
