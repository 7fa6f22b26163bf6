// Clocks and memory figures for latency profiling.
//
// All times are integer nanoseconds (int64: ~292 years of range). Wall time
// comes from CLOCK_MONOTONIC, which NTP may slew but never steps, so frame
// latencies are never negative; CPU times tell a frame that waited for the
// CPU (preempted, throttled) from one that computed for longer.
#pragma once

#include <sys/resource.h>
#include <time.h>

#include <cstdint>

namespace tristereo {

namespace detail {
inline std::int64_t clock_ns(clockid_t id) noexcept {
  timespec ts{};
  if (clock_gettime(id, &ts) != 0) return 0;
  return static_cast<std::int64_t>(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}
}  // namespace detail

// Wall time since an arbitrary fixed point (boot); only differences matter.
inline std::int64_t monotonic_ns() noexcept { return detail::clock_ns(CLOCK_MONOTONIC); }

// CPU time consumed by the calling thread.
inline std::int64_t thread_cpu_ns() noexcept { return detail::clock_ns(CLOCK_THREAD_CPUTIME_ID); }

// CPU time consumed by all threads of the process.
inline std::int64_t process_cpu_ns() noexcept { return detail::clock_ns(CLOCK_PROCESS_CPUTIME_ID); }

// Peak resident set size of the process so far (high-water mark), in bytes;
// 0 if unavailable. Linux reports ru_maxrss in KiB.
inline std::int64_t peak_rss_bytes() noexcept {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  return static_cast<std::int64_t>(usage.ru_maxrss) * 1024;
}

}  // namespace tristereo
