// WorkChunks: every item of the range is handed out exactly once, in chunks
// of the requested size, however many workers ask at once; a slow worker
// takes fewer chunks; reset() makes it reusable. HomeChunks: the same, and a
// worker takes its own home's items first, in order, then the other homes'.
// SideWork: the other workers take its chunks while worker 0 runs a serial
// step, drain() takes the rest, every chunk exactly once.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "platform/side_work.hpp"
#include "platform/thread_pool.hpp"
#include "platform/work_chunks.hpp"

namespace tristereo {
namespace {

TEST(WorkChunks, SingleWorkerGetsConsecutiveChunksThenFalse) {
  WorkChunks chunks;
  chunks.reset(3, 13, 4);
  int b = -1, e = -1;
  ASSERT_TRUE(chunks.next(&b, &e));
  EXPECT_EQ(b, 3);
  EXPECT_EQ(e, 7);
  ASSERT_TRUE(chunks.next(&b, &e));
  EXPECT_EQ(b, 7);
  EXPECT_EQ(e, 11);
  ASSERT_TRUE(chunks.next(&b, &e));  // the last one is shorter
  EXPECT_EQ(b, 11);
  EXPECT_EQ(e, 13);
  EXPECT_FALSE(chunks.next(&b, &e));
  EXPECT_FALSE(chunks.next(&b, &e));
}

TEST(WorkChunks, EmptyRangeAndChunkBelowOne) {
  WorkChunks chunks;
  int b = 0, e = 0;
  chunks.reset(5, 5, 3);
  EXPECT_FALSE(chunks.next(&b, &e));
  chunks.reset(0, 3, 0);  // treated as 1
  int count = 0;
  while (chunks.next(&b, &e)) {
    EXPECT_EQ(e - b, 1);
    ++count;
  }
  EXPECT_EQ(count, 3);
}

TEST(WorkChunks, EveryItemExactlyOnceAcrossPoolWorkers) {
  for (const int workers : {1, 2, 3, 8}) {
    ThreadPool pool;
    pool.start(workers, {}, /*pin=*/false);
    WorkChunks chunks;
    for (const int chunk : {1, 7, 64}) {
      constexpr int kItems = 10007;
      std::vector<std::atomic<int>> seen(kItems);
      chunks.reset(0, kItems, chunk);
      pool.run([&](int) {
        int b = 0, e = 0;
        while (chunks.next(&b, &e)) {
          EXPECT_LE(e - b, chunk);
          for (int i = b; i < e; ++i) seen[static_cast<std::size_t>(i)].fetch_add(1);
        }
      });
      for (int i = 0; i < kItems; ++i) {
        ASSERT_EQ(seen[static_cast<std::size_t>(i)].load(), 1)
            << "item " << i << ", " << workers << " workers, chunk " << chunk;
      }
    }
  }
}

TEST(WorkChunks, SlowWorkerTakesFewerChunks) {
  // Worker 0 sleeps on each chunk, worker 1 does not: worker 1 must end up
  // with most of the chunks (a static split would give each half).
  ThreadPool pool;
  pool.start(2, {}, /*pin=*/false);
  WorkChunks chunks;
  chunks.reset(0, 200, 1);
  int taken[2] = {0, 0};
  pool.run([&](int w) {
    int b = 0, e = 0;
    while (chunks.next(&b, &e)) {
      ++taken[w];
      if (w == 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  });
  EXPECT_EQ(taken[0] + taken[1], 200);
  EXPECT_GT(taken[1], taken[0]);
}

TEST(HomeChunks, HomesAreEqualBandsClampedToTheItemCount) {
  HomeChunks items;
  items.reset(10, 3);
  ASSERT_EQ(items.homes(), 3);
  int b = -1, e = -1;
  items.home_range(0, &b, &e);
  EXPECT_EQ(b, 0);
  EXPECT_EQ(e, 3);
  items.home_range(1, &b, &e);
  EXPECT_EQ(b, 3);
  EXPECT_EQ(e, 6);
  items.home_range(2, &b, &e);
  EXPECT_EQ(b, 6);
  EXPECT_EQ(e, 10);
  items.reset(2, 8);  // more workers than items: one item per home
  EXPECT_EQ(items.homes(), 2);
  items.reset(0, 4);
  EXPECT_EQ(items.homes(), 1);
  int calls = 0;
  items.for_each(3, [&](int) { ++calls; });
  EXPECT_EQ(calls, 0);
  items.reset(1000, 1000);
  EXPECT_EQ(items.homes(), HomeChunks::kMaxHomes);
}

TEST(HomeChunks, OneCallerTakesItsHomeFirstThenTheNextHomes) {
  HomeChunks items;
  items.reset(10, 2);
  std::vector<int> order;
  items.for_each(1, [&](int i) { order.push_back(i); });
  EXPECT_EQ(order, (std::vector<int>{5, 6, 7, 8, 9, 0, 1, 2, 3, 4}));
  items.reset(9, 3);
  order.clear();
  items.for_each(5, [&](int i) { order.push_back(i); });  // worker 5: home 5 % 3
  EXPECT_EQ(order, (std::vector<int>{6, 7, 8, 0, 1, 2, 3, 4, 5}));
  order.clear();
  items.for_each(0, [&](int i) { order.push_back(i); });  // all taken already
  EXPECT_TRUE(order.empty());
}

TEST(HomeChunks, EveryItemExactlyOnceAcrossPoolWorkers) {
  for (const int workers : {1, 2, 3, 8}) {
    ThreadPool pool;
    pool.start(workers, {}, /*pin=*/false);
    HomeChunks items;
    for (const int count : {0, 1, 5, 64, 10007}) {
      std::vector<std::atomic<int>> seen(static_cast<std::size_t>(count));
      items.reset(count, workers);
      pool.run([&](int worker) { items.for_each(worker, [&](int i) { seen[static_cast<std::size_t>(i)].fetch_add(1); }); });
      for (int i = 0; i < count; ++i) {
        ASSERT_EQ(seen[static_cast<std::size_t>(i)].load(), 1)
            << "item " << i << ", " << workers << " workers, " << count << " items";
      }
    }
  }
}

TEST(HomeChunks, SlowWorkerIsHelpedWithItsHome) {
  // Worker 0 sleeps on each item: worker 1 finishes its own home, then takes
  // most of worker 0's.
  ThreadPool pool;
  pool.start(2, {}, /*pin=*/false);
  HomeChunks items;
  items.reset(200, 2);
  int taken_from_home0[2] = {0, 0};
  pool.run([&](int w) {
    items.for_each(w, [&](int i) {
      if (i < 100) ++taken_from_home0[w];
      if (w == 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    });
  });
  EXPECT_EQ(taken_from_home0[0] + taken_from_home0[1], 100);
  EXPECT_GT(taken_from_home0[1], taken_from_home0[0]);
}

TEST(HomeChunks, NextClaimsInTheOrderOfForEach) {
  HomeChunks items;
  items.reset(9, 3);
  std::vector<int> order;
  int i = 0;
  while (items.next(5, &i)) order.push_back(i);  // worker 5: home 5 % 3
  EXPECT_EQ(order, (std::vector<int>{6, 7, 8, 0, 1, 2, 3, 4, 5}));
  EXPECT_FALSE(items.next(0, &i));
}

TEST(SideWork, EveryRowOnceBesideSerialStepsAndDrain) {
  for (const int workers : {1, 2, 3}) {
    ThreadPool pool;
    pool.start(workers, {}, /*pin=*/false);
    for (const int rows : {0, 1, 7, 480}) {
      std::vector<std::atomic<int>> seen(static_cast<std::size_t>(rows));
      // In the first serial step, a chunk taken beside it waits (10 s at
      // most) until the step has begun, and the step waits until such a chunk
      // is done: proof that the side work runs beside it, whatever the timing.
      std::atomic<int> done_beside{0};
      std::atomic<bool> first_step{false}, serial_running{false}, serial_over{false};
      const auto wait_for = [](const auto& ready) {
        const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        while (!ready() && std::chrono::steady_clock::now() < until) std::this_thread::yield();
      };
      const auto task = [&](int worker, int y0, int y1) {
        EXPECT_GE(worker, 0);
        EXPECT_LT(worker, workers);
        EXPECT_LE(y1 - y0, 4);
        for (int y = y0; y < y1; ++y) seen[static_cast<std::size_t>(y)].fetch_add(1);
        if (first_step.load()) {
          wait_for([&] { return serial_running.load() || serial_over.load(); });
          if (serial_running.load()) done_beside.fetch_add(y1 - y0);
        }
      };
      SideWork side(0, rows, 4, workers, task);
      int serial_calls = 0;
      const std::thread::id owner = std::this_thread::get_id();
      for (int step = 0; step < 3; ++step) {
        first_step.store(step == 0);
        serial_over.store(false);
        side.beside(&pool, [&] {
          EXPECT_EQ(std::this_thread::get_id(), owner);  // the serial step runs on the calling thread
          ++serial_calls;
          serial_running.store(true);
          if (step == 0 && workers > 1 && rows >= 8) wait_for([&] { return done_beside.load() > 0; });
          serial_running.store(false);
          serial_over.store(true);
        });
        first_step.store(false);
      }
      EXPECT_EQ(serial_calls, 3);
      if (workers > 1 && rows >= 8) {
        EXPECT_GT(done_beside.load(), 0) << workers << " workers, " << rows << " rows";
      }
      if (workers == 1) {
        EXPECT_EQ(done_beside.load(), 0);  // nobody beside the serial step
      }
      pool.run([&](int worker) { side.drain(worker); });
      for (int y = 0; y < rows; ++y)
        ASSERT_EQ(seen[static_cast<std::size_t>(y)].load(), 1) << "row " << y << ", " << workers << " workers";
    }
  }
}

TEST(SideWork, WithoutAPoolTheSerialStepRunsAlone) {
  int rows_done = 0;
  const auto task = [&](int, int y0, int y1) { rows_done += y1 - y0; };
  SideWork side(10, 30, 4, 1, task);
  int serial_calls = 0;
  side.beside(nullptr, [&] { ++serial_calls; });
  EXPECT_EQ(serial_calls, 1);
  EXPECT_EQ(rows_done, 0);
  side.drain(0);
  EXPECT_EQ(rows_done, 20);
}

}  // namespace
}  // namespace tristereo
