// Dynamic hand-out of a range in chunks to the workers of one ThreadPool::run.
//
// A static split makes a stage wait for its slowest worker, and a worker can
// be slow for reasons outside the program: another process on its core, a
// busy neighbour on a shared VM host, a core at a lower clock. With chunks
// taken on demand, a slowed worker simply takes fewer of them. Only work
// whose result does not depend on which worker does it (and in what order)
// may be split this way; the pipeline's rows, rows of tiles and the fill's
// invalid samples are such work (docs/threads.md lists every stage), so the
// output stays identical at any thread count.
//
//   WorkChunks rows;
//   rows.reset(0, height, 4);            // before run()
//   pool.run([&](int worker) {
//     int y0, y1;
//     while (rows.next(&y0, &y1)) { ... rows [y0, y1) ... }
//   });
//
// HomeChunks adds locality: each worker owns a home, a fixed band of the
// range, and takes its own items first; only then does it help the other
// homes. Use it when the same items come back run after run, or when a
// worker's consecutive items share work (the census costs' chunks of rows
// reuse the rows above them): a worker then mostly meets the data it touched
// last, still in its own core's caches, while a slow worker is still covered
// by the others.
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

// Items [0, count) in homes: home h is the band
// [h * count / homes, (h + 1) * count / homes). Taken one item at a time.
//
//   HomeChunks regions;
//   regions.reset(region_count, pool.size());  // before run()
//   pool.run([&](int worker) {
//     regions.for_each(worker, [&](int i) { ... item i ... });
//   });
class HomeChunks {
 public:
  static constexpr int kMaxHomes = 64;

  // homes is clamped to 1 .. min(count, kMaxHomes) (at least 1). Not
  // thread-safe: call it before the run() that hands the items out.
  void reset(int count, int homes) {
    count_ = std::max(0, count);
    homes_ = std::max(1, std::min({homes, count_, kMaxHomes}));
    for (int h = 0; h < homes_; ++h) {
      int b = 0, e = 0;
      home_range(h, &b, &e);
      chunks_[h].reset(b, e, 1);
    }
  }

  int homes() const { return homes_; }

  // Items [*b, *e) of home h (0 <= h < homes()).
  void home_range(int h, int* b, int* e) const {
    *b = static_cast<int>(static_cast<long long>(count_) * h / homes_);
    *e = static_cast<int>(static_cast<long long>(count_) * (h + 1) / homes_);
  }

  // Calls fn(i) for the items this worker claims: its home's (worker %
  // homes()), then the next homes' in turn. Every item goes to exactly one
  // caller. Safe to call from every worker at once.
  template <class Fn>
  void for_each(int worker, Fn&& fn) {
    for (int k = 0; k < homes_; ++k) {
      WorkChunks& home = chunks_[(worker + k) % homes_];
      int i = 0, i_end = 0;
      while (home.next(&i, &i_end)) fn(i);
    }
  }

  // Claims one item in the same order as for_each: true with *i, false when
  // every item is taken.
  bool next(int worker, int* i) {
    for (int k = 0; k < homes_; ++k) {
      int i_end = 0;
      if (chunks_[(worker + k) % homes_].next(i, &i_end)) return true;
    }
    return false;
  }

 private:
  WorkChunks chunks_[kMaxHomes];
  int count_ = 0;
  int homes_ = 1;
};

}  // namespace tristereo
