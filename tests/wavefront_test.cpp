// Wavefront: every tile handed out exactly once, never before the tiles it
// waits for (its left neighbour, the band above `lead` tiles ahead, the bands
// more than in_flight back), for any worker count (more workers than cores
// included); one worker goes band by band in raster order; a worker slowed on
// purpose takes fewer tiles and does not hold the run back.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "platform/thread_pool.hpp"
#include "platform/wavefront.hpp"

namespace tristereo {
namespace {

struct Shape {
  int bands, cols, lead, in_flight;
};

// Runs the wavefront on `workers` workers; each tile checks its
// dependencies when it starts. Returns the tiles each worker took.
std::vector<int> run_checked(const Shape& s, int workers, int slow_worker = -1) {
  ThreadPool pool;
  pool.start(workers, {}, /*pin=*/false);
  Wavefront wf;
  wf.configure(s.bands);
  wf.reset(s.bands, s.cols, s.lead, s.in_flight);
  const std::size_t tiles = static_cast<std::size_t>(s.bands) * static_cast<std::size_t>(s.cols);
  std::vector<std::atomic<int>> done(tiles), started(tiles);
  std::atomic<int> violations{0};
  std::vector<int> taken(static_cast<std::size_t>(workers), 0);
  std::atomic<int> finished{0}, finished_by_others{0};
  const auto at = [&](int k, int c) { return static_cast<std::size_t>(k) * static_cast<std::size_t>(s.cols) + static_cast<std::size_t>(c); };
  pool.run([&](int w) {
    int k = -1, c = 0;
    while (wf.next(&k, &c)) {
      if (started[at(k, c)].fetch_add(1) != 0) violations.fetch_add(1);
      if (c > 0 && done[at(k, c - 1)].load(std::memory_order_acquire) == 0) violations.fetch_add(1);
      if (k > 0 && done[at(k - 1, std::min(s.cols - 1, c + s.lead))].load(std::memory_order_acquire) == 0)
        violations.fetch_add(1);
      if (k >= s.in_flight && done[at(k - s.in_flight, s.cols - 1)].load(std::memory_order_acquire) == 0)
        violations.fetch_add(1);
      ++taken[static_cast<std::size_t>(w)];
      done[at(k, c)].store(1, std::memory_order_release);
      const bool band_done = wf.finish(k, c);
      if (band_done != (c == s.cols - 1)) violations.fetch_add(1);
      finished.fetch_add(1);
      if (w != slow_worker) {
        finished_by_others.fetch_add(1);
      } else {
        // Slowed on purpose, and by the others' progress rather than by a
        // clock: before its next tile it waits until the others finished
        // three more (or every tile is done). It holds no tile meanwhile, so
        // they can always go on; a sleep of a fixed time instead failed when
        // the machine's load starved the other worker.
        const int mark = finished_by_others.load() + 3;
        while (finished_by_others.load() < mark && finished.load() < static_cast<int>(tiles))
          std::this_thread::sleep_for(std::chrono::microseconds(50));
      }
    }
  });
  EXPECT_EQ(violations.load(), 0);
  int total = 0;
  for (std::size_t t = 0; t < tiles; ++t) {
    EXPECT_EQ(started[t].load(), 1) << "tile " << t;
    total += done[t].load();
  }
  EXPECT_EQ(total, static_cast<int>(tiles));
  return taken;
}

TEST(Wavefront, EveryTileOnceAfterItsDependencies) {
  const Shape shapes[] = {{1, 1, 0, 1}, {7, 1, 0, 2}, {1, 9, 3, 1}, {40, 20, 1, 3},
                          {30, 13, 0, 17}, {25, 8, 2, 5}, {17, 5, 9, 2}};
  for (const Shape& s : shapes)
    for (int workers : {1, 2, 3, 8, 16}) {
      SCOPED_TRACE(::testing::Message() << s.bands << "x" << s.cols << " lead " << s.lead << " in flight "
                                        << s.in_flight << ", " << workers << " workers");
      run_checked(s, workers);
    }
}

TEST(Wavefront, OneWorkerGoesBandByBandInOrder) {
  Wavefront wf;
  wf.configure(6);
  wf.reset(6, 4, 1, 3);
  int k = -1, c = 0, expected = 0;
  while (wf.next(&k, &c)) {
    EXPECT_EQ(k * 4 + c, expected);
    ++expected;
    wf.finish(k, c);
  }
  EXPECT_EQ(expected, 24);
  EXPECT_FALSE(wf.next(&k, &c));
}

TEST(Wavefront, NoBandsIsNoWork) {
  Wavefront wf;
  wf.configure(4);
  wf.reset(0, 5, 1, 2);
  int k = 0, c = 0;
  EXPECT_FALSE(wf.next(&k, &c));
}

TEST(Wavefront, ResetReusesTheState) {
  Wavefront wf;
  wf.configure(3);
  for (int round = 0; round < 3; ++round) {
    wf.reset(3, 2, 0, 1);
    int k = -1, c = 0, count = 0;
    while (wf.next(&k, &c)) {
      wf.finish(k, c);
      ++count;
    }
    EXPECT_EQ(count, 6);
  }
}

TEST(Wavefront, SlowWorkerTakesFewerTiles) {
  // Worker 0 waits after each of its tiles until the other has done three
  // more: with tiles taken on demand, the other worker does most of them (a
  // static split, such as a band each, would leave each half).
  const std::vector<int> taken = run_checked({20, 12, 1, 3}, 2, /*slow_worker=*/0);
  EXPECT_GT(taken[1], 2 * taken[0]) << "worker 0 (slow) took " << taken[0] << ", worker 1 " << taken[1];
}

}  // namespace
}  // namespace tristereo
