// An attacker on the same host, built from the IDL: floods a server's request or command topic with samples
// that each declare a new client or engine id, from one participant and writer, as fast as the writer goes
// (bounded by COUNT and a 60 s limit). Used by tests/e2e/dds_flood_test.sh to show that the server's per-peer
// state stays bounded. Usage: hapticd-dds-flood requests|commands|answered DOMAIN DEVICE COUNT [HOLD_S]
// answered: a client that reads its replies, as the client library and Python do - GET_PARAMETER requests under
// one client id, at most 32 unanswered at a time (every reply answered and read).
// DEVICE "*": a new device name in every sample too. HOLD_S: stay (with every instance registered) this long
// after the flood (at most 60 s).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <thread>

#include "hapticd/dds/conversion.hpp"
#include "hapticd/dds/endpoints.hpp"

using namespace hapticd;

int main(int argc, char** argv) {
  if (argc != 5 && argc != 6) {
    std::fprintf(stderr, "usage: %s requests|commands|answered DOMAIN DEVICE COUNT [HOLD_S]\n", argv[0]);
    return 2;
  }
  const std::string_view what = argv[1];
  const int domain = std::atoi(argv[2]);
  const char* device = argv[3];
  const long count = std::atol(argv[4]);
  dds::Participant participant(dds::ParticipantOptions{domain, {}, {}});
  dds::Writer<hapticd_msg_ControlRequest> requests(participant);
  dds::Writer<hapticd_msg_EngineCommand> commands(participant, dds::CommandTiming{0.05, 0.5});
  const auto start = std::chrono::steady_clock::now();
  if (what == "answered") {
    dds::Writer<hapticd_msg_ControlRequest> to_device(participant, {}, dds::target_partition(device));
    dds::Reader<hapticd_msg_ControlReply> replies(participant);
    while ((to_device.matched() == 0 || replies.matched() == 0) &&
           std::chrono::steady_clock::now() - start < std::chrono::seconds(10))
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    long sent = 0, answered = 0;
    while (answered < count && std::chrono::steady_clock::now() - start < std::chrono::seconds(60)) {
      while (sent < count && sent - answered < 32) {
        hapticd_msg_ControlRequest r{};
        dds::set_text(r.device, device);
        dds::set_text(r.client, "reader");
        r.request_id = static_cast<unsigned long long>(++sent);
        r.kind = hapticd_msg_REQUEST_GET_PARAMETER;
        dds::set_text(r.subject, "virtual_model.mass_kg");
        (void)to_device.write(r);
      }
      const int n = replies.take([](const hapticd_msg_ControlReply&, const dds_sample_info_t&) {});
      answered += n;
      if (n == 0) std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    std::printf("dds-flood: %ld requests sent, %ld replies read\n", sent, answered);
    return answered >= count ? 0 : 1;
  }
  while ((what == "requests" ? requests.matched() : commands.matched()) == 0 &&
         std::chrono::steady_clock::now() - start < std::chrono::seconds(10))
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  long sent = 0;
  for (long i = 0; i < count && std::chrono::steady_clock::now() - start < std::chrono::seconds(60); ++i) {
    const std::string id = "attacker-" + std::to_string(i);
    const std::string name = std::string_view(device) == "*" ? "device-" + std::to_string(i) : std::string(device);
    if (what == "requests") {
      hapticd_msg_ControlRequest r{};
      dds::set_text(r.device, name);
      dds::set_text(r.client, id);
      r.request_id = static_cast<unsigned long long>(i) + 1;
      r.kind = hapticd_msg_REQUEST_SET_PARAMETER;
      dds::set_text(r.subject, "virtual_model.mass_kg");
      r.value_count = 3;
      r.values[0] = r.values[1] = r.values[2] = 3.0;
      sent += requests.write(r) ? 1 : 0;
    } else {
      hapticd_msg_EngineCommand c{};
      dds::set_text(c.device, name);
      dds::set_text(c.engine, id);
      c.serial = 1;
      c.kind = hapticd_msg_COMMAND_WRENCH;
      c.command_pose.orientation[0] = 1.0;
      c.anchor.orientation[0] = 1.0;
      sent += commands.write(c) ? 1 : 0;
    }
    if (i % 1000 == 999) std::this_thread::sleep_for(std::chrono::milliseconds(1));  // let the loopback drain
  }
  std::printf("dds-flood: %ld %s written\n", sent, argv[1]);
  const double hold = argc == 6 ? std::min(60.0, std::atof(argv[5])) : 0.0;
  std::this_thread::sleep_for(std::chrono::duration<double>(std::max(1.0, hold)));  // reliable samples on their way
  return 0;
}
