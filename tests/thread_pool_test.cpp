// ThreadPool: every worker runs once per run(), results do not depend on the
// worker count, pinning really happens, bad CPUs fail fast, run() does not
// allocate, exceptions come back to the caller.
#include <gtest/gtest.h>
#include <sched.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "platform/affinity.hpp"
#include "platform/cpu_features.hpp"
#include "platform/realtime.hpp"
#include "platform/thread_pool.hpp"
#include "support/alloc_counter.hpp"
#include "support/keep_alive.hpp"
#include "tristereo/status.hpp"

namespace tristereo {
namespace {

TEST(ThreadPoolSplitRange, KnownBands) {
  int b = 0;
  int e = 0;
  const int expected[3][2] = {{0, 4}, {4, 7}, {7, 10}};
  for (int part = 0; part < 3; ++part) {
    ThreadPool::split_range(0, 10, 3, part, &b, &e);
    EXPECT_EQ(b, expected[part][0]);
    EXPECT_EQ(e, expected[part][1]);
  }
  // More parts than items: the first items get one each, the rest are empty.
  ThreadPool::split_range(5, 7, 4, 1, &b, &e);
  EXPECT_EQ(b, 6);
  EXPECT_EQ(e, 7);
  ThreadPool::split_range(5, 7, 4, 3, &b, &e);
  EXPECT_EQ(b, 7);
  EXPECT_EQ(e, 7);
}

TEST(ThreadPoolSplitRange, BandsTileTheRangeAndDifferByAtMostOne) {
  for (int begin : {-7, 0, 3}) {
    for (int length = 0; length <= 40; ++length) {
      for (int parts = 1; parts <= 12; ++parts) {
        int expected_begin = begin;
        int shortest = length + 1;
        int longest = -1;
        for (int part = 0; part < parts; ++part) {
          int b = 0;
          int e = 0;
          ThreadPool::split_range(begin, begin + length, parts, part, &b, &e);
          ASSERT_EQ(b, expected_begin) << begin << " " << length << " " << parts << " " << part;
          ASSERT_GE(e, b);
          shortest = std::min(shortest, e - b);
          longest = std::max(longest, e - b);
          expected_begin = e;
        }
        ASSERT_EQ(expected_begin, begin + length);
        ASSERT_LE(longest - shortest, 1);
      }
    }
  }
}

TEST(ThreadPoolSplitRange, RejectsBadArguments) {
  int b = 0;
  int e = 0;
  EXPECT_THROW(ThreadPool::split_range(5, 4, 1, 0, &b, &e), Error);
  EXPECT_THROW(ThreadPool::split_range(0, 4, 0, 0, &b, &e), Error);
  EXPECT_THROW(ThreadPool::split_range(0, 4, 2, 2, &b, &e), Error);
  EXPECT_THROW(ThreadPool::split_range(0, 4, 2, -1, &b, &e), Error);
  EXPECT_THROW(ThreadPool::split_range(0, 4, 2, 0, nullptr, &e), Error);
}

TEST(ThreadPool, UnstartedPoolRunsInlineAsOneWorker) {
  ThreadPool pool;
  EXPECT_EQ(pool.size(), 1);
  EXPECT_EQ(pool.worker_cpus(), std::vector<int>{-1});
  int calls = 0;
  std::thread::id ran_on;
  pool.run([&](int w) {
    EXPECT_EQ(w, 0);
    ++calls;
    ran_on = std::this_thread::get_id();
  });
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(ran_on, std::this_thread::get_id());
}

TEST(ThreadPool, EveryWorkerRunsExactlyOncePerRun) {
  for (int n : {1, 2, 3, 8}) {
    ThreadPool pool;
    pool.start(n, {}, false);
    ASSERT_EQ(pool.size(), n);
    std::vector<std::atomic<int>> counts(static_cast<size_t>(n));
    std::vector<std::thread::id> ids(static_cast<size_t>(n));
    constexpr int kRuns = 200;
    for (int r = 0; r < kRuns; ++r) {
      pool.run([&](int w) {
        counts[w].fetch_add(1);
        ids[w] = std::this_thread::get_id();
      });
    }
    for (int w = 0; w < n; ++w) EXPECT_EQ(counts[w].load(), kRuns) << "n=" << n << " w=" << w;
    // Worker 0 is the caller; the others are distinct background threads.
    EXPECT_EQ(ids[0], std::this_thread::get_id());
    EXPECT_EQ(std::set<std::thread::id>(ids.begin(), ids.end()).size(), static_cast<size_t>(n));
  }
}

// Runs spaced wider than the spin budget: every worker has blocked on the
// condition variable in between, so each run() goes through the wake-up path.
TEST(ThreadPool, RunsAfterWorkersBlockedStillReachEveryWorker) {
  ThreadPool pool;
  pool.start(2, {}, false);
  std::vector<std::atomic<int>> counts(2);
  constexpr int kRuns = 5;
  for (int r = 0; r < kRuns; ++r) {
    std::this_thread::sleep_for(std::chrono::nanoseconds(4 * pool.spin_ns()));
    pool.run([&](int w) { counts[w].fetch_add(1); });
  }
  for (int w = 0; w < 2; ++w) EXPECT_EQ(counts[w].load(), kRuns) << "w=" << w;
}

// A pinned pool pins its owner; a second pool started from that thread must
// still see (and pin its workers to) every CPU, and the pins unwind in order.
TEST(ThreadPool, SecondPoolFromTheSameThreadGetsEveryCpu) {
  const std::vector<int> allowed = allowed_cpus();
  ThreadPool first;
  first.start(0, {}, true);
  EXPECT_EQ(current_thread_affinity(), std::vector<int>{allowed[0]});
  EXPECT_EQ(ThreadPool::available_cpus(), allowed);
  {
    ThreadPool second;
    second.start(0, {}, true);
    EXPECT_EQ(second.size(), static_cast<int>(allowed.size()));
    EXPECT_EQ(second.worker_cpus(), allowed);
    const std::vector<std::vector<int>> read_back = second.read_back_worker_affinity();
    for (std::size_t i = 0; i < allowed.size(); ++i) {
      EXPECT_EQ(read_back[i], std::vector<int>{allowed[i]}) << "worker " << i;
    }
  }  // second.stop(): back to the first pool's pin
  EXPECT_EQ(current_thread_affinity(), std::vector<int>{allowed[0]});
  first.stop();
  EXPECT_EQ(current_thread_affinity(), allowed);
  EXPECT_EQ(ThreadPool::available_cpus(), allowed);
}

// Waiting threads spin long only when no two workers share a CPU.
TEST(ThreadPool, SpinsLongOnlyWhenEveryWorkerHasItsOwnCpu) {
  const std::vector<int> allowed = allowed_cpus();
  const int n = static_cast<int>(allowed.size());
  ThreadPool pool;
  pool.start(n, {}, true);
  const std::int64_t own_core_ns = pool.spin_ns();
  pool.start(n + 1, {}, true);
  const std::int64_t shared_core_ns = pool.spin_ns();
  EXPECT_LT(shared_core_ns, own_core_ns);
  EXPECT_EQ(own_core_ns, 500'000);
  EXPECT_EQ(shared_core_ns, 20'000);
  pool.start(2, {allowed[0], allowed[0]}, true);  // a CPU listed twice
  EXPECT_EQ(pool.spin_ns(), shared_core_ns);
  pool.start(n, {}, false);
  EXPECT_EQ(pool.spin_ns(), own_core_ns);
  pool.start(2 * n, {}, false);
  EXPECT_EQ(pool.spin_ns(), shared_core_ns);
  if (n >= 2) {
    pool.start(2, {allowed[0], allowed[1]}, true);
    EXPECT_EQ(pool.spin_ns(), own_core_ns);
  }
}

// A row-banded computation whose result must not depend on the worker count:
// each output row is a function of a 3-row neighbourhood of the input.
std::vector<std::uint32_t> banded_filter(ThreadPool& pool, const std::vector<std::uint32_t>& in,
                                         int width, int height) {
  std::vector<std::uint32_t> out(in.size());
  const int workers = pool.size();
  pool.run([&](int w) {
    int y0 = 0;
    int y1 = 0;
    ThreadPool::split_range(0, height, workers, w, &y0, &y1);
    for (int y = y0; y < y1; ++y) {
      std::uint32_t running = 0;
      for (int x = 0; x < width; ++x) {
        const int ya = std::max(y - 1, 0);
        const int yb = std::min(y + 1, height - 1);
        running = running * 31u + in[ya * width + x] + 2u * in[y * width + x] + in[yb * width + x];
        out[y * width + x] = running;
      }
    }
  });
  return out;
}

TEST(ThreadPool, BandedResultIdenticalForAnyWorkerCount) {
  const int width = 97;
  const int height = 61;
  std::vector<std::uint32_t> input(static_cast<size_t>(width * height));
  std::uint32_t state = 12345;
  for (auto& v : input) {
    state = state * 1664525u + 1013904223u;
    v = state >> 8;
  }
  ThreadPool serial;  // unstarted: one worker, the caller
  const std::vector<std::uint32_t> expected = banded_filter(serial, input, width, height);
  for (bool pin : {false, true}) {
    for (int n : {1, 2, 3, 8}) {
      ThreadPool pool;
      pool.start(n, {}, pin);
      EXPECT_EQ(banded_filter(pool, input, width, height), expected) << "n=" << n << " pin=" << pin;
    }
  }
}

TEST(ThreadPool, WorkersArePinnedToTheirCpus) {
  const std::vector<int> allowed = allowed_cpus();
  ThreadPool pool;
  pool.start(static_cast<int>(allowed.size()), {}, true);
  EXPECT_TRUE(pool.pinned());
  EXPECT_EQ(pool.worker_cpus(), allowed);
  const auto affinity = pool.read_back_worker_affinity();
  ASSERT_EQ(affinity.size(), allowed.size());
  for (size_t i = 0; i < allowed.size(); ++i) {
    EXPECT_EQ(affinity[i], std::vector<int>{allowed[i]}) << "worker " << i;
  }
}

TEST(ThreadPool, MoreWorkersThanCpusWrapAround) {
  const std::vector<int> allowed = allowed_cpus();
  // Reverse order, to show the list is taken as given.
  const std::vector<int> cpus(allowed.rbegin(), allowed.rend());
  const int n = static_cast<int>(cpus.size()) * 3 + 1;
  ThreadPool pool;
  pool.start(n, cpus, true);
  ASSERT_EQ(pool.size(), n);
  const auto affinity = pool.read_back_worker_affinity();
  const auto worker_cpus = pool.worker_cpus();
  for (int i = 0; i < n; ++i) {
    EXPECT_EQ(worker_cpus[i], cpus[i % cpus.size()]);
    EXPECT_EQ(affinity[i], std::vector<int>{cpus[i % cpus.size()]}) << "worker " << i;
  }
}

TEST(ThreadPool, UnpinnedWorkersKeepTheAllowedSet) {
  const std::vector<int> allowed = allowed_cpus();
  ThreadPool pool;
  pool.start(3, {}, false);
  EXPECT_FALSE(pool.pinned());
  EXPECT_EQ(pool.worker_cpus(), std::vector<int>(3, -1));
  for (const auto& cpus : pool.read_back_worker_affinity()) EXPECT_EQ(cpus, allowed);
}

TEST(ThreadPool, ZeroWorkersMeansOnePerCpu) {
  ThreadPool pool;
  pool.start(0, {}, false);
  EXPECT_EQ(pool.size(), static_cast<int>(allowed_cpus().size()));
  pool.start(0, {allowed_cpus()[0], allowed_cpus()[0]}, true);
  EXPECT_EQ(pool.size(), 2);
}

TEST(ThreadPool, StopRestoresTheCallersAffinity) {
  const std::vector<int> before = current_thread_affinity();
  const int last = before.back();
  {
    ThreadPool pool;
    pool.start(2, {last}, true);
    EXPECT_EQ(current_thread_affinity(), std::vector<int>{last});
    pool.stop();
    EXPECT_EQ(current_thread_affinity(), before);
    pool.start(2, {last}, true);
  }  // destructor
  EXPECT_EQ(current_thread_affinity(), before);
}

TEST(ThreadPool, PinningToACpuOutsideTheAllowedSetThrows) {
  const std::vector<int> allowed = allowed_cpus();
  const std::vector<int> before = current_thread_affinity();
  for (int bad : {1000000, allowed.back() + 1, -1}) {
    ThreadPool pool;
    try {
      pool.start(2, {allowed[0], bad}, true);
      FAIL() << "start accepted CPU " << bad;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kPlatform);
      const std::string message = e.what();
      EXPECT_NE(message.find("CPU " + std::to_string(bad)), std::string::npos) << message;
      EXPECT_NE(message.find("allowed CPUs: " + format_cpu_list(allowed)), std::string::npos)
          << message;
    }
    EXPECT_EQ(pool.size(), 1);
    EXPECT_EQ(current_thread_affinity(), before);
  }
}

TEST(ThreadPool, RejectedStartLeavesARunningPoolRunning) {
  ThreadPool pool;
  pool.start(3, {}, false);
  EXPECT_THROW(pool.start(2, {1000000}, true), Error);
  EXPECT_THROW(pool.start(-1, {}, false), Error);
  EXPECT_THROW(pool.start(ThreadPool::kMaxWorkers + 1, {}, false), Error);
  EXPECT_EQ(pool.size(), 3);
  std::atomic<int> calls{0};
  pool.run([&](int) { calls.fetch_add(1); });
  EXPECT_EQ(calls.load(), 3);
}

TEST(ThreadPool, BadWorkerCountIsInvalidArgument) {
  ThreadPool pool;
  try {
    pool.start(-3, {}, false);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(e.what()).find("-3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("1024"), std::string::npos) << e.what();
  }
}

TEST(ThreadPool, StartStopRestartLoop) {
  ThreadPool pool;
  for (int i = 0; i < 50; ++i) {
    const int n = 1 + i % 5;
    pool.start(n, {}, i % 2 == 0);
    std::atomic<int> sum{0};
    pool.run([&](int w) { sum.fetch_add(w + 1); });
    ASSERT_EQ(sum.load(), n * (n + 1) / 2) << "iteration " << i;
    if (i % 3 == 0) pool.stop();
    if (i % 7 == 0) pool.stop();  // idempotent
  }
  pool.stop();
  EXPECT_EQ(pool.size(), 1);
  EXPECT_EQ(current_thread_affinity(), allowed_cpus());
}

TEST(ThreadPool, ExceptionFromAWorkerReachesTheCaller) {
  ThreadPool pool;
  pool.start(4, {}, false);
  try {
    pool.run([](int w) {
      if (w == 2) throw std::runtime_error("worker 2 failed");
    });
    FAIL() << "run() swallowed the exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "worker 2 failed");
  }
  // Several failures: the lowest worker index wins, deterministically.
  for (int r = 0; r < 20; ++r) {
    try {
      pool.run([](int w) {
        if (w == 1 || w == 3) throw std::runtime_error("worker " + std::to_string(w));
      });
      FAIL();
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "worker 1");
    }
  }
  EXPECT_THROW(pool.run([](int w) {
                 if (w == 0) throw Error(ErrorCode::kInvalidArgument, "caller");
               }),
               Error);
  // The pool is still usable and the error slots were cleared.
  std::atomic<int> calls{0};
  pool.run([&](int) { calls.fetch_add(1); });
  EXPECT_EQ(calls.load(), 4);
}

TEST(ThreadPool, NestedRunIsRejected) {
  for (int n : {1, 3}) {
    ThreadPool pool;
    pool.start(n, {}, false);
    try {
      pool.run([&](int w) {
        if (w == 0) pool.run([](int) {});
      });
      FAIL() << "nested run accepted, n=" << n;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
    }
    std::atomic<int> calls{0};
    pool.run([&](int) { calls.fetch_add(1); });
    EXPECT_EQ(calls.load(), n);
  }
}

TEST(ThreadPool, AllocationCounterSeesAllocations) {
  // Positive control, so that the zero below means something.
  test::start_counting_allocations();
  // keep_alive: clang elides a new/delete pair nobody observes.
  auto* p = new int(7);
  test::keep_alive(p);
  auto* q = new std::vector<int>(100);
  test::keep_alive(q);
  test::keep_alive(q->data());
  std::thread([] {
    char* c = new char[3];
    test::keep_alive(c);
    delete[] c;
  }).join();
  const std::int64_t n = test::stop_counting_allocations();
  delete q;
  delete p;
  EXPECT_GE(n, 4);
}

TEST(ThreadPool, RunDoesNotAllocate) {
  for (int n : {1, 2, 4}) {
    for (bool pin : {false, true}) {
      ThreadPool pool;
      pool.start(n, {}, pin);
      std::vector<int> out(static_cast<size_t>(n), 0);
      auto task = [&](int w) { out[w] += w + 1; };
      pool.run(task);  // warm-up
      test::start_counting_allocations();
      for (int r = 0; r < 100; ++r) {
        pool.run(task);
        pool.run([&](int w) { out[w] -= 1; });  // a temporary capturing lambda too
      }
      const std::int64_t allocations = test::stop_counting_allocations();
      EXPECT_EQ(allocations, 0) << "n=" << n << " pin=" << pin;
      for (int w = 0; w < n; ++w) EXPECT_EQ(out[w], (w + 1) * 101 - 100);
    }
  }
}

#if defined(__SANITIZE_THREAD__) || defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif

TEST(ThreadPoolRealtime, RejectsBadPriorityBeforeTouchingAnything) {
  ThreadPool pool;
  pool.start(2, {}, false);
  for (int bad : {0, -5, max_realtime_priority() + 1}) {
    try {
      pool.set_realtime(bad);
      FAIL() << "priority " << bad << " accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
      EXPECT_NE(std::string(e.what()).find(std::to_string(bad)), std::string::npos) << e.what();
    }
  }
  pool.run([](int) { EXPECT_EQ(current_thread_scheduling().policy, SCHED_OTHER); });
}

TEST(ThreadPoolRealtime, AppliesToEveryWorkerOrChangesNothing) {
  if (kSanitized) {
    GTEST_SKIP() << "mlockall would try to lock the sanitizer's shadow memory";
  }
  const ThreadScheduling before = current_thread_scheduling();
  ThreadPool pool;
  pool.start(3, {}, false);
  std::vector<ThreadScheduling> seen(3);
  bool applied = false;
  try {
    pool.set_realtime(10);
    applied = true;
  } catch (const Error& e) {
    // Without privileges: a clear message, and every worker as it was.
    EXPECT_EQ(e.code(), ErrorCode::kPlatform);
    const std::string message = e.what();
    EXPECT_TRUE(message.find("CAP_SYS_NICE") != std::string::npos ||
                message.find("CAP_IPC_LOCK") != std::string::npos)
        << message;
  }
  pool.run([&](int w) { seen[w] = current_thread_scheduling(); });
  for (int w = 0; w < 3; ++w) {
    EXPECT_EQ(seen[w].policy, applied ? SCHED_FIFO : before.policy) << "worker " << w;
    EXPECT_EQ(seen[w].priority, applied ? 10 : before.priority) << "worker " << w;
  }
  pool.stop();
  EXPECT_EQ(current_thread_scheduling().policy, before.policy);
  EXPECT_EQ(current_thread_scheduling().priority, before.priority);
}

}  // namespace
}  // namespace tristereo
