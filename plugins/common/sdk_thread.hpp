#pragma once
// A thread of its own for a vendor SDK's calls, so that a call that never returns (a USB transfer that hangs, a
// driver that waits for a device that is gone) cannot hold the loop: the device plugin posts a job (a function it
// made at configure time: posting allocates nothing) and waits for it with a deadline; a job that misses its
// deadline leaves the loop free to fault the device, naming the SDK call it is stuck in.
//
//   The loop:      post(job), then wait(until_ns); busy() while a job runs; stuck_in() names its vendor call.
//   Not the loop:  run(job, seconds) - configure's open, calibration, close - the same, with a deadline in seconds.
//   A job:         calling("dhdGetPosition") before each vendor call, so a fault can say which one hangs.
//   The end:       stop(grace_s, keep): the thread ends after its job; if the job is stuck in the SDK past the grace,
//                  the thread is left to it (detached) holding `keep` (whatever its jobs touch) and the plugin's own
//                  library is pinned in memory, so a call that returns after the device is gone touches nothing
//                  freed or unloaded.
//
// The thread runs at the scheduling priority of the thread that last posted to it (the loop's SCHED_FIFO, when the
// loop has one), taken on the SDK's thread, not the loop's. Lock-free: two counters and futexes.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <thread>

namespace hapticd::plugins {

class SdkThread {
 public:
  using Job = std::function<void()>;

  // Starts the thread (idle until a job is posted). `name`: the thread's name (at most 15 characters).
  explicit SdkThread(const char* name);
  // stop(0.5 s) when not stopped yet.
  ~SdkThread();
  SdkThread(const SdkThread&) = delete;
  SdkThread& operator=(const SdkThread&) = delete;

  // Any thread but a job: `job` runs next on the SDK's thread. False (and nothing posted) while the previous job
  // still runs. `job` must outlive its run (the plugin's own member, made once). `next_post_ns`
  // (CLOCK_MONOTONIC; 0: unknown) is when the plugin expects to post the job after this one - the next cycle's
  // reads: the SDK's thread is awake for it then, so the hand-off costs no wake-up. Real-time safe.
  bool post(const Job& job, std::int64_t next_post_ns = 0) noexcept;
  // Waits until the posted job has finished, at most until `until_ns` (CLOCK_MONOTONIC). False: it still runs.
  // Real-time safe (a futex wait, bounded).
  bool wait(std::int64_t until_ns) noexcept;
  // post() and wait() with a deadline `seconds` from now; false: busy or not finished in time. Not real-time.
  bool run(const Job& job, double seconds) noexcept;
  // A job is running (posted and not finished).
  [[nodiscard]] bool busy() const noexcept;
  // The vendor call the running job is in (static text; "" when between calls) and since when (CLOCK_MONOTONIC).
  [[nodiscard]] const char* stuck_in() const noexcept;
  [[nodiscard]] std::int64_t stuck_since_ns() const noexcept;

  // A job, on the SDK's thread: it is entering `call` (static text: a string literal).
  void calling(const char* call) noexcept;

  // Ends the thread after its job, waiting at most `grace_s`. True: it ended. False: the job is stuck in the SDK;
  // the thread is detached and keeps `keep` alive until its job returns, and the library holding this code stays
  // loaded. Not real-time.
  bool stop(double grace_s, std::shared_ptr<void> keep = nullptr) noexcept;

 private:
  struct Shared;
  static void main(const std::shared_ptr<Shared>& shared) noexcept;

  std::shared_ptr<Shared> shared_;
  std::thread thread_;
  bool stopped_ = false;
};

}  // namespace hapticd::plugins
