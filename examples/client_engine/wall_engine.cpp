// A minimal impedance-type rendering engine on the installed client library: a wall normal to x, 2 cm ahead of
// the handle's start, rendered through the server's virtual coupling. Every state is answered from the state
// callback (Cyclone's receive thread) with the proxy: the handle's pose, held back at the wall.
//   wall_engine [--domain D] [--device NAME] [--duration S] [--push N]
// --push asks the simulated operator to push with N newtons along +x once the device is claimed.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

#include "hapticd/client/client.hpp"

namespace {
int run(int argc, char** argv) {
  int domain = 0;
  std::string device = "vishard3";
  double duration_s = 10.0, push_n = 0.0;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--domain")
      domain = std::atoi(argv[i + 1]);
    else if (flag == "--device")
      device = argv[i + 1];
    else if (flag == "--duration")
      duration_s = std::atof(argv[i + 1]);
    else if (flag == "--push")
      push_n = std::atof(argv[i + 1]);
    else {
      std::fprintf(stderr, "unknown option %s\n", argv[i]);
      return 2;
    }
  }
  using namespace std::chrono_literals;
  hapticd::client::Client client({"wall-engine", domain});
  const auto first = client.wait_for_state(device, 20s);
  if (!first) {
    std::fprintf(stderr, "no state from '%s' on domain %d\n", device.c_str(), domain);
    return 1;
  }
  const double wall_x = first->pose.position.x() + 0.02;
  std::atomic<std::uint64_t> answered{0};
  std::atomic<double> deepest{0.0};
  const hapticd::client::Reply claim = client.claim(device);
  if (!claim.accepted) {
    std::fprintf(stderr, "claim refused: %s\n", claim.message.c_str());
    return 1;
  }
  client.on_state([&](const hapticd::client::DeviceState& s) {
    if (s.device != device) return;
    hapticd::Pose proxy = s.pose;
    if (proxy.position.x() > wall_x) {
      deepest.store(std::max(deepest.load(), proxy.position.x() - wall_x));
      proxy.position.x() = wall_x;
    }
    client.send_coupling(device, proxy, hapticd::Twist{}, s.serial);
    answered.fetch_add(1);
  });
  if (push_n != 0.0) client.operator_command(device, "push", {push_n, 0.0, 0.0, 0.2});
  std::this_thread::sleep_for(std::chrono::duration<double>(duration_s));
  client.on_state({});
  const auto last = client.latest_state(device);
  client.release(device);
  std::printf("answered %llu states; handle %.4f m past the start, the wall at 0.0200 m, deepest %.4f m into it\n",
              static_cast<unsigned long long>(answered.load()), last ? last->pose.position.x() - (wall_x - 0.02) : 0.0,
              deepest.load());
  return answered.load() > 0 ? 0 : 1;
}
}  // namespace

// Every error ends with a message and exit code 2, never an abort: a DDS participant that cannot be made (a
// malformed HAPTICD_DDS_NETWORK, a Cyclone configuration or DDS Security refusing it), a bad client id.
int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "wall_engine: %s\n", e.what());
    return 2;
  }
}
