// What this machine itself allows when threads are added: the same loop run
// by 1 and by 2 pinned threads at once, each on its own data. The ratio of
// items_per_second (2 threads / 1 thread) is the ceiling for a stage whose
// work looks like that loop; docs/performance.md compares the pipeline's
// thread speed-ups with it.
//
//   machine/alu/threads:N             register-only arithmetic (no memory)
//   machine/random_read/<KiB>/threads:N
//                                     independent random 4-byte reads over a
//                                     private buffer of <KiB> per thread, the
//                                     access pattern of the tritree's node walks
//
// On a VM, cores that look private may share caches and memory bandwidth with
// other tenants: the random_read ceiling beyond the L2 size shows it.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "platform/affinity.hpp"

namespace tristereo {
namespace {

// Pins benchmark thread i to the i-th allowed CPU, so two threads never share
// one CPU; reports an error instead of measuring an unpinned run.
bool pin_benchmark_thread(benchmark::State& state) {
  static const std::vector<int> cpus = current_thread_affinity();
  if (cpus.empty()) {
    state.SkipWithError("cannot read this thread's CPU set");
    return false;
  }
  const int i = state.thread_index();
  if (i >= static_cast<int>(cpus.size())) {
    state.SkipWithError("more benchmark threads than allowed CPUs");
    return false;
  }
  std::string error;
  if (!pin_current_thread(cpus[static_cast<std::size_t>(i)], &error)) {
    state.SkipWithError(error.c_str());
    return false;
  }
  return true;
}

// 64-bit LCG step (Knuth's MMIX constants): a dependent chain of multiplies.
inline std::uint64_t lcg(std::uint64_t x) {
  return x * 6364136223846793005ull + 1442695040888963407ull;
}

void bench_alu(benchmark::State& state) {
  if (!pin_benchmark_thread(state)) return;
  constexpr int kStepsPerIteration = 4096;
  std::uint64_t x = 1 + static_cast<std::uint64_t>(state.thread_index());
  for (auto _ : state) {
    for (int i = 0; i < kStepsPerIteration; ++i) x = lcg(x);
    benchmark::DoNotOptimize(x);
  }
  state.SetItemsProcessed(state.iterations() * kStepsPerIteration);
}

void bench_random_read(benchmark::State& state) {
  if (!pin_benchmark_thread(state)) return;
  const std::size_t words = static_cast<std::size_t>(state.range(0)) * 1024 / sizeof(std::uint32_t);
  // Allocated and touched by the reading thread, before timing.
  std::vector<std::uint32_t> buffer(words, 1);
  const std::uint64_t mask = words - 1;  // words is a power of two
  constexpr int kReadsPerIteration = 4096;
  std::uint64_t x = 7 + static_cast<std::uint64_t>(state.thread_index());
  std::uint64_t sum = 0;
  for (auto _ : state) {
    for (int i = 0; i < kReadsPerIteration; ++i) {
      x = lcg(x);
      sum += buffer[static_cast<std::size_t>((x >> 33) & mask)];
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * kReadsPerIteration);
}

const bool registered = [] {
  benchmark::RegisterBenchmark("machine/alu", bench_alu)->UseRealTime()->Threads(1)->Threads(2);
  // 1 MiB fits a 2 MiB L2; 4 and 16 MiB per thread do not.
  for (int kib : {1024, 4096, 16384}) {
    benchmark::RegisterBenchmark("machine/random_read", bench_random_read)
        ->Arg(kib)
        ->UseRealTime()
        ->Threads(1)
        ->Threads(2);
  }
  return true;
}();

}  // namespace
}  // namespace tristereo

BENCHMARK_MAIN();
