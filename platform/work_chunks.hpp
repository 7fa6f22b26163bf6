// Dynamic hand-out of a range in chunks to the workers of one ThreadPool::run.
//
// A static split makes a stage wait for its slowest worker, and a worker can
// be slow for reasons outside the program: another process on its core, a
// busy neighbour on a shared VM host, a core at a lower clock. With chunks
// taken on demand, a slowed worker simply takes fewer of them. Only work
// whose result does not depend on which worker does it (and in what order)
// may be split this way; the pipeline's rows, triangles and tritree regions
// are such work, so the output stays identical at any thread count.
//
//   WorkChunks rows;
//   rows.reset(0, height, 4);            // before run()
//   pool.run([&](int worker) {
//     int y0, y1;
//     while (rows.next(&y0, &y1)) { ... rows [y0, y1) ... }
//   });
#pragma once

#include <algorithm>
#include <atomic>

namespace tristereo {

class WorkChunks {
 public:
  // [begin, end) in chunks of `chunk` (>= 1) items, the last one shorter.
  // Not thread-safe: call it before the run() that hands the chunks out.
  // end + (workers + 1) * chunk must fit in an int (each worker overshoots
  // at most once); the pipeline's ranges are below 2^25.
  void reset(int begin, int end, int chunk) {
    next_.store(begin, std::memory_order_relaxed);
    end_ = end;
    chunk_ = std::max(1, chunk);
  }

  // Claims the next chunk: true with [*b, *e) non-empty, false when all are
  // taken. Safe to call from every worker at once.
  bool next(int* b, int* e) {
    if (next_.load(std::memory_order_relaxed) >= end_) return false;
    const int start = next_.fetch_add(chunk_, std::memory_order_relaxed);
    if (start >= end_) return false;
    *b = start;
    *e = std::min(end_, start + chunk_);
    return true;
  }

 private:
  // On its own cache line: every claim writes it.
  alignas(64) std::atomic<int> next_{0};
  alignas(64) int end_ = 0;
  int chunk_ = 1;
};

}  // namespace tristereo
