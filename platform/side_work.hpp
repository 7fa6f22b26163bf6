// Work that a pool's other workers take while worker 0 runs a serial step.
//
// A frame has short steps that only one thread can do (the tritree's carry
// across tile borders and its pick of the stretched leaves); with two
// workers, the second one would spin through them. Work that is ready
// earlier than it is needed, and whose result does not depend on which
// worker does it, fills that time: the pipeline hands the tritree the
// preparation of the right image's rows (MatchContext::prepare_right_rows),
// and the matching stage takes whatever is left.
//
//   SideWork side(0, height, 4, [&](int worker, int y0, int y1) { ... rows ... });
//   side.beside(&pool, [&] { serial_step(); });   // any number of times
//   pool.run([&](int worker) { side.drain(worker); });  // the rest
#pragma once

#include <algorithm>
#include <atomic>

#include "platform/function_ref.hpp"
#include "platform/thread_pool.hpp"
#include "platform/work_chunks.hpp"

namespace tristereo {

class SideWork {
 public:
  // [begin, end) in chunks of `chunk` items, each done by task(worker, b, e)
  // on whichever worker takes it. `task` must outlive this object, so it is
  // taken as a named callable only (a lambda written in the call would be
  // gone by the time a worker calls it).
  // Worker w takes the chunks of its home first (HomeChunks, `homes` bands
  // of the range), so that the matching stage, whose workers start from the
  // same bands, finds its rows in its own core's caches.
  template <class Task>
  SideWork(int begin, int end, int chunk, int homes, Task& task)
      : begin_(begin), end_(end), chunk_(std::max(1, chunk)), task_(task) {
    chunks_.reset((end - begin + chunk_ - 1) / chunk_, homes);
  }
  SideWork(const SideWork&) = delete;
  SideWork& operator=(const SideWork&) = delete;

  // Runs serial() on the calling thread (the pool's owner) while the pool's
  // other workers take chunks until it returns; each finishes the chunk it
  // holds, so a chunk should cost microseconds. Without a pool of two or
  // more workers: serial() alone.
  void beside(ThreadPool* pool, FunctionRef<void()> serial) {
    if (pool == nullptr || pool->size() < 2) {
      serial();
      return;
    }
    serial_done_.store(false, std::memory_order_relaxed);
    pool->run([&](int worker) {
      if (worker == 0) {
        serial();
        serial_done_.store(true, std::memory_order_relaxed);
        return;
      }
      while (!serial_done_.load(std::memory_order_relaxed) && take(worker)) {
      }
    });
  }

  // Inside a run(), on every worker: takes chunks until none are left.
  void drain(int worker) {
    while (take(worker)) {
    }
  }

 private:
  bool take(int worker) {
    int i = 0;
    if (!chunks_.next(worker, &i)) return false;
    const int b = begin_ + i * chunk_;
    task_(worker, b, std::min(end_, b + chunk_));
    return true;
  }

  int begin_, end_, chunk_;
  HomeChunks chunks_;
  FunctionRef<void(int, int, int)> task_;
  std::atomic<bool> serial_done_{false};
};

}  // namespace tristereo
