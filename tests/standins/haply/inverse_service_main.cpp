// The Inverse Service stand-in as a process, for end-to-end runs of the shipped Haply sessions: listens on
// 127.0.0.1:PORT until killed; the hand pushes with the given force, holds the grip's buttons (a, b, c as bits 0,
// 1, 2) and the Inverse3 has the given id.
// Usage: hapticd-standin-inverse-service PORT [FX FY FZ [BUTTONS [DEVICE_ID]]]
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "inverse_service_standin.hpp"

int main(int argc, char** argv) {
  if (argc != 2 && (argc < 5 || argc > 7)) {
    std::fprintf(stderr, "usage: %s PORT [FX FY FZ [BUTTONS [DEVICE_ID]]]\n", argv[0]);
    return 2;
  }
  hapticd::standins::InverseServiceStandIn::Options options;
  options.port = std::atoi(argv[1]);
  if (argc >= 7) options.device_id = argv[6];
  hapticd::standins::InverseServiceStandIn service(options);
  const unsigned buttons = argc >= 6 ? static_cast<unsigned>(std::strtoul(argv[5], nullptr, 0)) : 0u;
  if (argc >= 5) service.hand(std::atof(argv[2]), std::atof(argv[3]), std::atof(argv[4]), buttons);
  std::printf("inverse service stand-in on %s\n", service.url().c_str());
  std::fflush(stdout);
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGINT);
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  int signal = 0;
  sigwait(&set, &signal);
  return 0;
}
