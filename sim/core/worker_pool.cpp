#include "sim/core/worker_pool.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

#if defined(__linux__)
#include <sched.h>
#endif

namespace vf {
namespace {

// How long a thread that has run out of blocks keeps polling for the next run() (a worker) or
// for the last blocks to finish (the caller) before it sleeps. Waking a sleeping thread took
// 13-50 us of the waker's time and 50-100 us before the woken thread ran (2 vCPUs of an AMD
// EPYC under Firecracker, condition variable, the worker idle 20 us-2 ms before), against about
// 5 us per run() while the worker polls; a step of 1,000 rocks runs the pool two to five times
// with 0.1-0.6 ms of serial work between, so the window spans a step's serial work. OpenMP
// runtimes do the same (libgomp polls before it sleeps unless told not to).
constexpr std::chrono::microseconds kSpin{2000};

void pause() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

// The processors this process may run on: its affinity mask where the system has one (taskset,
// cpusets), else the machine's count; 0 if unknown.
int usableProcessors() {
#if defined(__linux__)
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) return CPU_COUNT(&set);
#endif
  return static_cast<int>(std::thread::hardware_concurrency());
}

}  // namespace

struct WorkerPool::Impl {
  std::vector<std::thread> workers;
  std::mutex mutex;
  std::condition_variable wake;
  bool stopping = false;
  std::uint32_t generation = 0;          // of the current run(); written under the mutex
  std::atomic<std::uint32_t> posted{0};  // the same, readable without the mutex
  const std::function<void(int)>* work = nullptr;
  int count = 0;
  // The next block to claim, with the generation it belongs to in the high half: a worker that
  // wakes late for an earlier run() can never claim a block of a later one.
  std::atomic<std::uint64_t> claim{0};
  std::atomic<int> finished{0};  // blocks of the current run() that have returned

  void drain(std::uint32_t g, const std::function<void(int)>& fn, int n) {
    std::uint64_t v = claim.load(std::memory_order_acquire);
    while ((v >> 32) == g && static_cast<int>(v & 0xFFFFFFFFu) < n) {
      if (!claim.compare_exchange_weak(v, v + 1, std::memory_order_acq_rel)) continue;
      fn(static_cast<int>(v & 0xFFFFFFFFu));
      if (finished.fetch_add(1, std::memory_order_acq_rel) + 1 == n) finished.notify_all();
      v = claim.load(std::memory_order_acquire);
    }
  }

  // Waits while busy() holds, at most kSpin, without giving up the processor. Only where
  // every thread of the pool can have a processor of its own (set before the workers start).
  bool spins = false;
  template <class Pred>
  void spinWhile(Pred busy) const {
    if (!spins) return;
    const auto until = std::chrono::steady_clock::now() + kSpin;
    for (int i = 1; busy(); ++i) {
      pause();
      if (i % 64 == 0 && std::chrono::steady_clock::now() > until) return;
    }
  }

  void loop() {
    std::uint32_t seen = 0;
    for (;;) {
      spinWhile([&] { return posted.load(std::memory_order_acquire) == seen; });
      std::unique_lock lock(mutex);
      wake.wait(lock, [&] { return stopping || generation != seen; });
      if (stopping) return;
      seen = generation;
      const std::function<void(int)>* fn = work;
      const int n = count;
      lock.unlock();
      drain(seen, *fn, n);  // claims nothing if that run() has already been finished
    }
  }
};

WorkerPool::WorkerPool(int threads) : impl_(std::make_unique<Impl>()) {
  // Polling threads on shared processors would take turns that sleeping ones leave to others
  // (with `taskset -c 0`, 300 rocks on 2 polling threads run 2x slower than on one).
  const int cores = usableProcessors();
  impl_->spins = threads > 1 && cores > 0 && threads <= cores;
  for (int t = 1; t < threads; ++t) impl_->workers.emplace_back([this] { impl_->loop(); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard lock(impl_->mutex);
    impl_->stopping = true;
  }
  impl_->posted.fetch_add(1, std::memory_order_release);  // ends the workers' polling now
  impl_->wake.notify_all();
  for (std::thread& t : impl_->workers) t.join();
}

int WorkerPool::threads() const { return static_cast<int>(impl_->workers.size()) + 1; }

bool WorkerPool::polls() const { return impl_->spins; }

void WorkerPool::run(int count, const std::function<void(int)>& work) {
  if (count <= 0) return;
  Impl& p = *impl_;
  if (p.workers.empty() || count == 1) {
    for (int i = 0; i < count; ++i) work(i);
    return;
  }
  std::uint32_t g;
  {
    std::lock_guard lock(p.mutex);
    g = ++p.generation;
    p.posted.store(g, std::memory_order_release);
    p.work = &work;
    p.count = count;
    p.finished.store(0, std::memory_order_relaxed);
    p.claim.store(static_cast<std::uint64_t>(g) << 32, std::memory_order_release);
  }
  p.wake.notify_all();
  p.drain(g, work, count);
  // Only blocks that a running thread claimed are left: wait for those.
  p.spinWhile([&] { return p.finished.load(std::memory_order_acquire) != count; });
  for (int f; (f = p.finished.load(std::memory_order_acquire)) != count;)
    p.finished.wait(f, std::memory_order_acquire);
}

void WorkerPool::forRanges(WorkerPool* pool, int count, int grain,
                           const std::function<void(int, int)>& work) {
  if (count <= 0) return;
  const int ranges = pool ? std::min(pool->threads() * 4, count / std::max(1, grain)) : 1;
  if (ranges < 2) {
    work(0, count);
    return;
  }
  pool->run(ranges, [&](int r) {
    work(static_cast<int>(static_cast<std::int64_t>(count) * r / ranges),
         static_cast<int>(static_cast<std::int64_t>(count) * (r + 1) / ranges));
  });
}

}  // namespace vf
