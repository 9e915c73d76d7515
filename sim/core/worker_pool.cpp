#include "sim/core/worker_pool.h"

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace vf {

struct WorkerPool::Impl {
  std::vector<std::thread> workers;
  std::mutex mutex;
  std::condition_variable wake;
  bool stopping = false;
  std::uint32_t generation = 0;  // of the current run(); written under the mutex
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

  void loop() {
    std::uint32_t seen = 0;
    for (;;) {
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
  for (int t = 1; t < threads; ++t) impl_->workers.emplace_back([this] { impl_->loop(); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard lock(impl_->mutex);
    impl_->stopping = true;
  }
  impl_->wake.notify_all();
  for (std::thread& t : impl_->workers) t.join();
}

int WorkerPool::threads() const { return static_cast<int>(impl_->workers.size()) + 1; }

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
    p.work = &work;
    p.count = count;
    p.finished.store(0, std::memory_order_relaxed);
    p.claim.store(static_cast<std::uint64_t>(g) << 32, std::memory_order_release);
  }
  p.wake.notify_all();
  p.drain(g, work, count);
  // Only blocks that a running thread claimed are left: wait for those.
  for (int f; (f = p.finished.load(std::memory_order_acquire)) != count;)
    p.finished.wait(f, std::memory_order_acquire);
}

}  // namespace vf
