// Software prefetch of a run of cache lines.
#pragma once

#include <cstddef>

namespace tristereo {

// Prefetches [p, p + bytes) a 64-byte line at a time, for reading (kWrite = 0)
// or writing (1).
template <int kWrite>
inline void prefetch_lines(const void* p, std::size_t bytes) {
  const char* c = static_cast<const char*>(p);
  for (std::size_t b = 0; b < bytes; b += 64) {
    __builtin_prefetch(c + b, kWrite);
    // GCC 12 at -O3 deletes a loop whose only statements are prefetches (they
    // have no side effect it must keep): an empty volatile asm keeps the loop
    // without ordering any memory access.
    asm volatile("" : : "r"(c + b));
  }
}

}  // namespace tristereo
