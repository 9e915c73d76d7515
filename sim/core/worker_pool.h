// Threads kept for the life of a World, for a step's work split into numbered blocks (the
// narrow phase's blocks of collider pairs, the solver's runs of islands).
//
// Why kept and not started per step: a thread started per step has to be scheduled before the
// step can end, and on a machine whose other cores are busy that takes milliseconds: 300 rocks
// on 2 threads run 3x slower than on one while a build runs beside them. Here a worker that is
// not running when the blocks run out is never waited for (the caller has done its share), so
// a loaded machine costs at most what one thread costs. A thread out of blocks polls for up to
// 2 ms before it sleeps, where the pool's threads do not outnumber the machine's (waking a
// sleeping thread cost 50-100 us on the development VM; worker_pool.cpp). Which thread runs a
// block changes no result: the callers give each block its own output and merge them in block
// order.
#pragma once

#include <functional>
#include <memory>

namespace vf {

class WorkerPool {
 public:
  // `threads` in all, counting the caller: threads - 1 workers are started.
  explicit WorkerPool(int threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int threads() const;
  // Whether threads out of blocks poll before they sleep: more than one thread, and no more
  // than the processors this process may run on (its affinity mask: `taskset`, cpusets).
  bool polls() const;
  // Calls work(i) once for every i in [0, count), on the calling thread and on the workers that
  // are free, and returns when every call has returned. `work` must not throw.
  void run(int count, const std::function<void(int)>& work);

  // Calls work(begin, end) for consecutive ranges that cover [0, count) once, each at least
  // `grain` long (shorter ones cost more to hand to another thread than they save), on the
  // threads of `pool`, or as one range on the calling thread if pool is null or count < 2
  // grain. For per-body loops whose bodies are independent: each body is handled as it would
  // be alone, so the results are the same bits for any thread count.
  static void forRanges(WorkerPool* pool, int count, int grain,
                        const std::function<void(int, int)>& work);
  // The grain of the per-body loops of a step (posing colliders, the solver's motions,
  // integration): a body takes 40-60 ns in each (1,000 rocks on the cliff), so fewer bodies
  // than this are not worth handing to another thread.
  static constexpr int kBodiesPerRange = 64;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vf
