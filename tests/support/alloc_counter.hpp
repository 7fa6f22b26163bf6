// Counting heap allocations in tests, to prove that a hot path (pool run(),
// Pipeline::process()) allocates nothing.
//
//   tristereo::test::start_counting_allocations();
//   pool.run(task);
//   EXPECT_EQ(tristereo::test::stop_counting_allocations(), 0);
//
// Every global operator new / new[] (plain, nothrow, aligned, aligned nothrow)
// is replaced for the whole test executable; while counting is on, each call
// from any thread adds one. malloc/calloc called directly are not counted.
// Warm up first (one untimed call) so that lazily created state, e.g. the
// first use of a thread_local or an iostream, is not counted.
#pragma once

#include <cstdint>

namespace tristereo::test {

// Resets the counter to 0 and starts counting.
void start_counting_allocations();

// Stops counting and returns the number of allocations since the start.
std::int64_t stop_counting_allocations();

}  // namespace tristereo::test
