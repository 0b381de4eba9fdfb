#include "sdk_thread.hpp"

#include <dlfcn.h>
#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <chrono>

#include "hapticd/realtime/tick_signal.hpp"

namespace hapticd::plugins {

using realtime::TickSignal;

struct SdkThread::Shared {
  std::atomic<std::uint32_t> posted{0};  // futex word: jobs posted (and the stop, which counts as one)
  std::atomic<std::uint32_t> done{0};    // futex word: jobs finished
  std::atomic<const Job*> job{nullptr};
  std::atomic<bool> stopping{false};
  std::atomic<const char*> call{""};
  std::atomic<std::int64_t> call_since_ns{0};
  std::atomic<pthread_t> poster{0};          // the thread that last posted: its priority is taken
  std::atomic<std::int64_t> expected_ns{0};  // when the plugin expects to post the job after this one (0: unknown)
  std::shared_ptr<void> keep;                // set before `stopping` when the thread is left to a stuck job
};

SdkThread::SdkThread(const char* name) : shared_(std::make_shared<Shared>()) {
  thread_ = std::thread([shared = shared_] { main(shared); });
  (void)pthread_setname_np(thread_.native_handle(), name);
}

SdkThread::~SdkThread() {
  if (!stopped_) (void)stop(0.5);
}

namespace {

// A futex wake-up costs 50-100 us on a virtual machine (docs/devices.md): twice a cycle would be a 2 kHz loop's
// whole budget. So each side spins a little (yielding the CPU between looks) before it sleeps: the loop for its
// job's end, the SDK's thread for the next job - right after a job (the cycle's next call comes at once) and from
// shortly before the time the plugin expects the next one (the next cycle's reads). Never for long: a thread at
// the loop's SCHED_FIFO priority that spun all the time would be throttled by the kernel.
constexpr std::int64_t kLoopSpinNs = 300'000;      // the loop, waiting for its job's end
constexpr std::int64_t kAfterJobSpinNs = 100'000;  // the SDK's thread, right after a job
constexpr std::int64_t kAheadNs = 200'000;         // the SDK's thread wakes this much before the expected job

// Spins while `word` holds `expected`, at most until `until_ns`; true: it changed.
bool spin_while(const std::atomic<std::uint32_t>& word, std::uint32_t expected, std::int64_t until_ns) noexcept {
  for (int i = 0;; ++i) {
    if (word.load(std::memory_order_acquire) != expected) return true;
    if ((i & 15) == 15 && TickSignal::now_ns() >= until_ns) return false;
    (void)sched_yield();
  }
}

// The SDK's thread: waits for a job after `seen`; `expected_ns` (0: none) is when the plugin expects the next.
void await_job(const std::atomic<std::uint32_t>& posted, std::uint32_t seen, std::int64_t expected_ns) noexcept {
  const std::int64_t now = TickSignal::now_ns();
  if (spin_while(posted, seen, now + kAfterJobSpinNs)) return;
  if (expected_ns > now) {
    // Asleep until shortly before it is due (a post wakes it sooner), then awake for it.
    if (expected_ns - kAheadNs > TickSignal::now_ns())
      (void)TickSignal::wait_while(posted, seen, expected_ns - kAheadNs);
    if (spin_while(posted, seen, expected_ns + kAheadNs)) return;
  }
  (void)TickSignal::wait_while(posted, seen, TickSignal::now_ns() + 1'000'000'000);
}

}  // namespace

void SdkThread::main(const std::shared_ptr<Shared>& s) noexcept {
  std::uint32_t seen = 0;
  pthread_t adopted = 0;
  for (;;) {
    while (s->posted.load(std::memory_order_acquire) == seen)
      await_job(s->posted, seen, s->expected_ns.load(std::memory_order_relaxed));
    if (s->stopping.load(std::memory_order_acquire)) {
      s->keep.reset();  // a job that was stuck has returned: what it touched goes now, on this thread
      return;
    }
    seen = s->posted.load(std::memory_order_acquire);
    if (const pthread_t p = s->poster.load(std::memory_order_relaxed); p != 0 && p != adopted) {
      sched_param param{};
      int policy = 0;
      if (pthread_getschedparam(p, &policy, &param) == 0) (void)pthread_setschedparam(pthread_self(), policy, &param);
      adopted = p;
    }
    const Job* job = s->job.load(std::memory_order_acquire);
    if (job != nullptr && *job) (*job)();
    s->call.store("", std::memory_order_relaxed);
    s->done.store(seen, std::memory_order_release);
    TickSignal::wake(s->done);
  }
}

bool SdkThread::busy() const noexcept {
  return shared_->done.load(std::memory_order_acquire) != shared_->posted.load(std::memory_order_acquire);
}

bool SdkThread::post(const Job& job, std::int64_t next_post_ns) noexcept {
  if (stopped_ || busy()) return false;
  shared_->expected_ns.store(next_post_ns, std::memory_order_relaxed);
  shared_->poster.store(pthread_self(), std::memory_order_relaxed);
  shared_->job.store(&job, std::memory_order_release);
  shared_->posted.fetch_add(1, std::memory_order_release);
  TickSignal::wake(shared_->posted);
  return true;
}

bool SdkThread::wait(std::int64_t until_ns) noexcept {
  const std::uint32_t target = shared_->posted.load(std::memory_order_acquire);
  {
    const std::uint32_t d = shared_->done.load(std::memory_order_acquire);
    if (d == target) return true;
    if (spin_while(shared_->done, d, std::min(until_ns, TickSignal::now_ns() + kLoopSpinNs)) &&
        shared_->done.load(std::memory_order_acquire) == target)
      return true;
  }
  for (;;) {
    const std::uint32_t d = shared_->done.load(std::memory_order_acquire);
    if (d == target) return true;
    if (!TickSignal::wait_while(shared_->done, d, until_ns))
      return shared_->done.load(std::memory_order_acquire) == target;
  }
}

bool SdkThread::run(const Job& job, double seconds) noexcept {
  if (!post(job)) return false;
  return wait(TickSignal::now_ns() + static_cast<std::int64_t>(seconds * 1e9));
}

const char* SdkThread::stuck_in() const noexcept { return shared_->call.load(std::memory_order_relaxed); }

std::int64_t SdkThread::stuck_since_ns() const noexcept {
  return shared_->call_since_ns.load(std::memory_order_relaxed);
}

void SdkThread::calling(const char* call) noexcept {
  shared_->call_since_ns.store(TickSignal::now_ns(), std::memory_order_relaxed);
  shared_->call.store(call, std::memory_order_relaxed);
}

bool SdkThread::stop(double grace_s, std::shared_ptr<void> keep) noexcept {
  if (stopped_) return true;
  stopped_ = true;
  const bool ended = wait(TickSignal::now_ns() + static_cast<std::int64_t>(grace_s * 1e9));
  if (!ended) {
    // Left to its job: what the job touches stays alive with the thread, and this code stays mapped (the plugin's
    // library is made undeletable: unloading it would pull the code from under a call that returns later).
    shared_->keep = std::move(keep);
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&SdkThread::main), &info) != 0 && info.dli_fname != nullptr)
      (void)dlopen(info.dli_fname, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
  }
  shared_->stopping.store(true, std::memory_order_release);
  shared_->posted.fetch_add(1, std::memory_order_release);
  TickSignal::wake(shared_->posted);
  if (ended)
    thread_.join();
  else
    thread_.detach();
  return ended;
}

}  // namespace hapticd::plugins
