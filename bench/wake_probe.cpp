// wake_probe: a periodic real-time thread like cyclictest's, with the two things hapticd's loop has and
// cyclictest's has not, each switchable - work that touches memory after every wake-up, and other threads in
// the process - to tell which of them makes the loop's wake-ups slower (bench/trace_wakeups.py --probe).
//
//   wake_probe [--rate 2000] [--seconds 5] [--priority 80] [--cpu -1] [--touch-kb 0] [--threads 0]
//
// Every period the thread sleeps to its absolute deadline (clock_nanosleep, CLOCK_MONOTONIC, TIMER_ABSTIME),
// notes how late it woke, then writes one byte per cache line of a --touch-kb buffer (a loop's cycle touching
// its state; 0: nothing, as cyclictest). --threads other threads sleep in the process (as the server's DDS,
// log and command threads). Memory is locked and the CPU latency limit held at 0 (as cyclictest -m does).
// Prints the wake-up latency's p50, p99, p99.9 and max in us.
#include <fcntl.h>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <thread>
#include <vector>

namespace {

struct Options {
  int rate = 2000;
  double seconds = 5.0;
  int priority = 80;
  int cpu = -1;
  int touch_kb = 0;
  int threads = 0;
};

std::int64_t to_ns(const timespec& t) { return std::int64_t{t.tv_sec} * 1000000000 + t.tv_nsec; }

timespec from_ns(std::int64_t ns) {
  timespec t{};
  t.tv_sec = static_cast<time_t>(ns / 1000000000);
  t.tv_nsec = static_cast<long>(ns % 1000000000);
  return t;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i];
    const char* value = argv[i + 1];
    if (key == "--rate") {
      o.rate = std::atoi(value);
    } else if (key == "--seconds") {
      o.seconds = std::atof(value);
    } else if (key == "--priority") {
      o.priority = std::atoi(value);
    } else if (key == "--cpu") {
      o.cpu = std::atoi(value);
    } else if (key == "--touch-kb") {
      o.touch_kb = std::atoi(value);
    } else if (key == "--threads") {
      o.threads = std::atoi(value);
    } else {
      std::fprintf(stderr, "wake_probe: unknown option %s\n", argv[i]);
      std::exit(2);
    }
  }
  if (argc % 2 == 0 || o.rate <= 0 || o.seconds <= 0.0 || o.touch_kb < 0 || o.threads < 0) {
    std::fprintf(stderr,
                 "usage: wake_probe [--rate HZ] [--seconds S] [--priority P] [--cpu N] [--touch-kb KB] "
                 "[--threads N]\n");
    std::exit(2);
  }
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
    std::perror("wake_probe: mlockall");
  }
  const int latency_fd = open("/dev/cpu_dma_latency", O_WRONLY);
  const std::int32_t zero = 0;
  if (latency_fd < 0 || write(latency_fd, &zero, sizeof zero) != sizeof zero) {
    std::perror("wake_probe: /dev/cpu_dma_latency");
  }
  std::atomic<bool> stop{false};
  std::vector<std::thread> others;
  for (int i = 0; i < o.threads; ++i) {
    others.emplace_back([&stop] {
      while (!stop.load()) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      }
    });
  }
  const std::int64_t cycles = static_cast<std::int64_t>(o.seconds * o.rate);
  std::vector<std::int64_t> late(static_cast<std::size_t>(cycles));
  std::vector<unsigned char> touched(static_cast<std::size_t>(o.touch_kb) * 1024 + 1);
  int failed = 0;
  std::thread loop([&] {
    pthread_setname_np(pthread_self(), "wake-probe");
    if (o.cpu >= 0) {
      cpu_set_t set;
      CPU_ZERO(&set);
      CPU_SET(o.cpu, &set);
      failed |= pthread_setaffinity_np(pthread_self(), sizeof set, &set);
    }
    sched_param param{};
    param.sched_priority = o.priority;
    failed |= pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
    const std::int64_t period = 1000000000 / o.rate;
    timespec now{};
    clock_gettime(CLOCK_MONOTONIC, &now);
    std::int64_t deadline = to_ns(now) + period;
    for (std::int64_t i = 0; i < cycles; ++i) {
      const timespec t = from_ns(deadline);
      clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &t, nullptr);
      clock_gettime(CLOCK_MONOTONIC, &now);
      late[static_cast<std::size_t>(i)] = to_ns(now) - deadline;
      volatile unsigned char* bytes = touched.data();  // volatile: the stores are the point
      for (std::size_t b = 0; b + 1 < touched.size(); b += 64) {
        bytes[b] = static_cast<unsigned char>(bytes[b] + 1);
      }
      deadline += period;
    }
  });
  loop.join();
  stop = true;
  for (std::thread& t : others) {
    t.join();
  }
  if (failed != 0) {
    std::fprintf(stderr, "wake_probe: could not set the CPU or SCHED_FIFO (run as root)\n");
    return 1;
  }
  std::sort(late.begin(), late.end());
  const auto at = [&](double p) {
    return static_cast<double>(late[std::min(late.size() - 1, static_cast<std::size_t>(p * late.size()))]) / 1e3;
  };
  std::printf("wake_probe touch %d KB, %d threads: p50 %.1f p99 %.1f p99.9 %.1f max %.1f us (%zu wake-ups)\n",
              o.touch_kb, o.threads, at(0.5), at(0.99), at(0.999), static_cast<double>(late.back()) / 1e3, late.size());
  return 0;
}
