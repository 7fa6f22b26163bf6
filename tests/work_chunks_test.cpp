// WorkChunks: every item of the range is handed out exactly once, in chunks
// of the requested size, however many workers ask at once; a slow worker
// takes fewer chunks; reset() makes it reusable. HomeChunks: the same, and a
// worker takes its own home's items first, in order, then the other homes'.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

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

}  // namespace
}  // namespace tristereo
