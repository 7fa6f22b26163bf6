// Large working buffers: uninitialised, and backed by transparent huge pages
// where the system offers them.
//
// A frame's first touch of a buffer costs one page fault per 4 KiB page: for
// the path matcher's per-sample tables (hundreds of bytes per sample) that
// was a third of a one-shot `tristereo match` (docs/performance.md, "One-shot
// match"). The 2 MiB-aligned part of a block (malloc serves large blocks
// by mmap) is advised MADV_HUGEPAGE, so a fault there brings in 2 MiB at
// once; the pages are still only touched when a frame writes them (a frame
// smaller than the configured maximum leaves the rest untouched, at 2 MiB
// granularity). Nothing is over-allocated for alignment, so the heap holds
// exactly what working_memory_bytes() reports. Without THP (or outside Linux)
// the advice is a no-op. Trivial element types only.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <type_traits>

#include "platform/huge_pages.hpp"

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace tristereo {

struct FreeDelete {
  void operator()(void* p) const noexcept { std::free(p); }
};

template <class T>
using LargeArray = std::unique_ptr<T[], FreeDelete>;

constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;

// platform/huge_pages.hpp decides: huge pages unless the environment says
// TRISTEREO_HUGE_PAGES=0 or the machine is a VM whose balloon reports free
// pages to the host (there a huge page fault after idle costs far more).
inline bool huge_pages_wanted() { return huge_page_policy().advise; }

// Advises the 2 MiB-aligned part of [p, p + bytes) for transparent huge pages
// (the buffers reserved elsewhere, e.g. std::vector capacities). Advice only:
// an error (no THP, not Linux) changes nothing.
inline void advise_huge_pages(const void* p, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  if (!huge_pages_wanted()) return;
  const std::uintptr_t begin = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t first = (begin + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
  const std::uintptr_t last = (begin + bytes) / kHugePageBytes * kHugePageBytes;
  if (p != nullptr && last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#else
  (void)p;
  (void)bytes;
#endif
}

// n elements, uninitialised. Throws std::bad_alloc.
template <class T>
LargeArray<T> large_array(std::size_t n) {
  static_assert(std::is_trivial<T>::value, "large_array holds trivial types only");
  const std::size_t bytes = n * sizeof(T) > 0 ? n * sizeof(T) : 1;
  void* p = std::malloc(bytes);
  if (p == nullptr) throw std::bad_alloc();
  advise_huge_pages(p, bytes);
  return LargeArray<T>(static_cast<T*>(p));
}

}  // namespace tristereo
