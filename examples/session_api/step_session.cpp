// Runs a session file in-process for a number of seconds in lockstep and prints where each device's handle is,
// what the operator pushes with, and the torque written: the session API in a few lines.
//   step_session SESSION.yaml [SECONDS] [OVERRIDE ...]      e.g. step_session s.yaml 2 server.seed=7
#include <cstdio>
#include <exception>
#include <string>

#include "hapticd/server/session.hpp"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SESSION.yaml [SECONDS] [OVERRIDE ...]\n", argv[0]);
    return 2;
  }
  const double seconds = argc > 2 ? std::stod(argv[2]) : 1.0;
  hapticd::server::SessionOptions options;
  for (int i = 3; i < argc; ++i) options.overrides.emplace_back(argv[i]);
  try {
    hapticd::server::Session session = hapticd::server::Session::from_file(argv[1], options);
    session.step(static_cast<std::uint64_t>(seconds / session.period_s() + 0.5));
    for (const std::string& name : session.device_names()) {
      const hapticd::server::DeviceView v = session.device(name);
      const auto& p = v.handle_pose.position;
      const auto& f = v.operator_wrench.force;
      std::printf(
          "%s: t %.4f s, scheme %s, fault %s, handle [%.4f %.4f %.4f] m, operator force [%.2f %.2f %.2f] N, "
          "torque norm %.3f N m\n",
          name.c_str(), v.time_s, v.scheme.c_str(), v.fault.empty() ? "none" : v.fault.c_str(), p.x(), p.y(), p.z(),
          f.x(), f.y(), f.z(), v.command.torque_nm.norm());
    }
    const hapticd::server::SessionStatistics s = session.statistics();
    std::printf("cycles %llu, compute p50 %.1f us, p99 %.1f us\n", static_cast<unsigned long long>(s.cycles),
                s.compute_p50_us, s.compute_p99_us);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  return 0;
}
