// WorkerPool (sim/core/worker_pool.h): every block runs exactly once per run(), its effects are
// visible when run() returns, and a worker that wakes late for an earlier run() never runs a
// block of a later one (the generation in the claim). Stressed with many short runs, whose
// workers often wake after the caller has done every block, so late wake-ups happen.
#include "sim/core/worker_pool.h"

#include <gtest/gtest.h>
#include <sched.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <utility>
#include <vector>

namespace vf {
namespace {

TEST(WorkerPool, EveryBlockRunsOnceAndIsDoneWhenRunReturns) {
  for (int threads = 1; threads <= 4; ++threads) {
    WorkerPool pool(threads);
    EXPECT_EQ(pool.threads(), threads);
    for (int round = 0; round < 4000; ++round) {
      const int count = round % 7;  // 0 and 1 included: the caller alone
      std::vector<int> calls(count, 0);
      std::atomic<int> total{0};
      // Each run writes its own round into the blocks it runs: a block of this run done by a
      // worker with the previous run's function would write the wrong value or miss a count.
      std::vector<int> seenRound(count, -1);
      pool.run(count, [&](int i) {
        ++calls[i];
        seenRound[i] = round;
        total.fetch_add(1, std::memory_order_relaxed);
      });
      ASSERT_EQ(total.load(), count) << threads << " threads, round " << round;
      for (int i = 0; i < count; ++i) {
        ASSERT_EQ(calls[i], 1) << threads << " threads, round " << round << ", block " << i;
        ASSERT_EQ(seenRound[i], round);
      }
    }
  }
}

// The pool's threads really share the work: with two threads, two blocks that each wait until
// both have started can both see the other start only if a worker runs one beside the caller.
// On one thread the first block would wait out its bound alone (10 s, so that a failure is a
// failure, not a hang) and only the second would see both started.
TEST(WorkerPool, AWorkerTakesBlocksBesideTheCaller) {
  WorkerPool pool(2);
  std::atomic<int> started{0};
  std::atomic<int> met{0};
  pool.run(2, [&](int) {
    started.fetch_add(1);
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (started.load() < 2 && std::chrono::steady_clock::now() < until)
      std::this_thread::yield();
    if (started.load() >= 2) met.fetch_add(1);
  });
  EXPECT_EQ(met.load(), 2) << "a block ran alone: no worker took one";
}

// Polling is for threads that each have a processor: a pool of two polls where the process may
// run on two processors or more, and not once it is pinned to one (there, a polling worker
// would hold the caller's only processor; 300 rocks on 2 threads ran 2x slower than on one).
TEST(WorkerPool, PollsOnlyWhereEveryThreadHasAProcessor) {
  EXPECT_FALSE(WorkerPool(1).polls());
  cpu_set_t all;
  ASSERT_EQ(sched_getaffinity(0, sizeof all, &all), 0);
  const int usable = CPU_COUNT(&all);
  EXPECT_EQ(WorkerPool(2).polls(), usable >= 2);
  EXPECT_FALSE(WorkerPool(usable + 1).polls());
  int first = 0;
  while (!CPU_ISSET(first, &all)) ++first;
  cpu_set_t one;
  CPU_ZERO(&one);
  CPU_SET(first, &one);
  ASSERT_EQ(sched_setaffinity(0, sizeof one, &one), 0);
  const bool pinnedPolls = WorkerPool(2).polls();
  ASSERT_EQ(sched_setaffinity(0, sizeof all, &all), 0);  // restored before any check can return
  EXPECT_FALSE(pinnedPolls);
}

// forRanges covers [0, count) with consecutive ranges, each once and none shorter than the
// grain, and keeps short loops (and loops without a pool) in one range on the caller.
TEST(WorkerPool, ForRangesCoversEveryIndexOnceInRangesOfAtLeastTheGrain) {
  WorkerPool pool(2);
  for (WorkerPool* p : {static_cast<WorkerPool*>(nullptr), &pool}) {
    for (int count : {0, 1, 63, 64, 127, 128, 129, 1000, 4099}) {
      std::vector<int> hits(count, 0);
      std::vector<std::pair<int, int>> ranges(64, {-1, -1});
      std::atomic<int> made{0};
      const std::thread::id caller = std::this_thread::get_id();
      std::atomic<bool> offCaller{false};
      WorkerPool::forRanges(p, count, 64, [&](int lo, int hi) {
        ranges[made.fetch_add(1)] = {lo, hi};
        for (int i = lo; i < hi; ++i) ++hits[i];
        if (std::this_thread::get_id() != caller) offCaller = true;
      });
      for (int i = 0; i < count; ++i) ASSERT_EQ(hits[i], 1) << count << " items, index " << i;
      const int n = made.load();
      if (count == 0) {
        EXPECT_EQ(n, 0);
        continue;
      }
      if (!p || count < 128) {
        EXPECT_EQ(n, 1) << count << " items";
        EXPECT_FALSE(offCaller.load());
        continue;
      }
      EXPECT_GT(n, 1) << count << " items";
      EXPECT_LE(n, 8) << "more than four ranges per thread";
      for (int r = 0; r < n; ++r) EXPECT_GE(ranges[r].second - ranges[r].first, 64);
    }
  }
}

}  // namespace
}  // namespace vf
