// What a benchmark run's context says about the binary itself.
#pragma once

#include <benchmark/benchmark.h>
#include <sys/stat.h>

#include <ctime>

namespace tristereo {

// The binary's link time (UTC) beside Google Benchmark's own date of the run.
// The library is linked in statically, so every library change relinks the
// benchmarks, and an old time here means an old binary: a build tree
// reconfigured with -DTRISTEREO_BUILD_BENCH=OFF keeps its last benchmarks,
// and `cmake --build` no longer touches them.
inline void add_binary_context() {
  struct stat st {};
  char text[32] = "unknown";
  std::tm tm{};
  if (stat("/proc/self/exe", &st) == 0 && gmtime_r(&st.st_mtime, &tm) != nullptr)
    std::strftime(text, sizeof text, "%Y-%m-%d %H:%M:%S UTC", &tm);
  benchmark::AddCustomContext("binary_linked", text);
}

}  // namespace tristereo
