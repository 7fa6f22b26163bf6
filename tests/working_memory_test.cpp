// Pipeline::working_memory_bytes() is the heap that configure() allocates:
// measured with the allocator's statistics (glibc's bytes in use, mmapped
// blocks included; AddressSanitizer's allocated bytes in its own build) around
// configure(), for several sizes, D, modes and thread counts.
// And configure() leaves the buffers outside the tritree untouched (resident
// set growth); docs/performance.md, "Working memory".
#include <gtest/gtest.h>

#include <malloc.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <memory>
#include <string>

#if defined(__SANITIZE_ADDRESS__)
#define TRISTEREO_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define TRISTEREO_TEST_ASAN 1
#endif
#endif
#ifdef TRISTEREO_TEST_ASAN
#include <sanitizer/allocator_interface.h>
#endif

#include "src/tritree/tritree.hpp"
#include "src/memory/large_array.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/synth.hpp"

namespace tristereo {
namespace {

// Heap bytes in use: small chunks (arena) + blocks served by mmap; under
// AddressSanitizer, whose allocator replaces glibc's, the bytes it has handed out.
std::int64_t heap_in_use() {
#ifdef TRISTEREO_TEST_ASAN
  return static_cast<std::int64_t>(__sanitizer_get_current_allocated_bytes());
#else
  const struct mallinfo2 mi = mallinfo2();
  return static_cast<std::int64_t>(mi.uordblks) + static_cast<std::int64_t>(mi.hblkhd);
#endif
}

// Resident pages of this process, in bytes (/proc/self/statm, second field).
std::int64_t resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  std::int64_t size_pages = 0, resident_pages = 0;
  statm >> size_pages >> resident_pages;
  return resident_pages * 4096;
}

PipelineConfig config_for(int w, int h, int ndisp, bool dense, int threads) {
  PipelineConfig c;
  c.max_width = w;
  c.max_height = h;
  c.params.num_disp = ndisp;
  c.params.dense = dense;
  c.threads = threads;
  c.pin_threads = false;
  return c;
}

TEST(WorkingMemory, ZeroUntilConfigured) {
  Pipeline p;
  EXPECT_EQ(p.working_memory_bytes(), 0u);
}

TEST(WorkingMemory, EqualsTheHeapThePipelineHolds) {
  struct Case {
    int w, h, ndisp;
    bool dense;
    int threads;
  };
  for (const Case& k : {Case{2, 2, 1, false, 1}, Case{64, 48, 16, false, 1}, Case{640, 480, 64, false, 1},
                        Case{640, 480, 128, true, 2}, Case{1242, 375, 80, false, 3}, Case{941, 490, 256, false, 2}}) {
    auto p = std::make_unique<Pipeline>();
    p->configure(config_for(k.w, k.h, k.ndisp, k.dense, k.threads));
    const auto reported = static_cast<std::int64_t>(p->working_memory_bytes());
    // The heap the configured pipeline holds: what destroying it gives back.
    const std::int64_t with = heap_in_use();
    p.reset();
    const std::int64_t held = with - heap_in_use();
    const std::string what = std::to_string(k.w) + "x" + std::to_string(k.h) + " D" + std::to_string(k.ndisp) +
                             (k.dense ? " dense" : " sparse") + " t" + std::to_string(k.threads);
    // Every byte reported is held...
    EXPECT_LE(reported, held) << what;
    // ...and the rest is bookkeeping: the allocator's chunk headers and the
    // page rounding of mmapped blocks (< 4 KiB each), the pipeline object, the
    // thread pool and the workers' small state. A buffer missing from the
    // accessor (the smallest size-dependent one holds max_height int32s)
    // would exceed this on the large cases.
    // The default model adds about 16 mmapped buffers (costs, paths, fill,
    // census, the right view's copies): up to 4 KiB of rounding each.
    const std::int64_t slack = 128 * 1024 + 16 * 1024 * k.threads;
    EXPECT_LE(held - reported, slack) << what << ": held " << held << ", reported " << reported;
  }
}

TEST(WorkingMemory, GrowsWithTheConfiguredPixels) {
  Pipeline small, large;
  small.configure(config_for(320, 240, 64, false, 1));
  large.configure(config_for(640, 480, 64, false, 1));
  const double per_px_small = static_cast<double>(small.working_memory_bytes()) / (320.0 * 240.0);
  const double per_px_large = static_cast<double>(large.working_memory_bytes()) / (640.0 * 480.0);
  // Linear in the pixels up to per-row and per-worker parts: the same bytes per
  // pixel within 10 %.
  EXPECT_NEAR(per_px_small, per_px_large, 0.1 * per_px_large);
}

TEST(WorkingMemory, ConfigureTouchesOnlyTheTritreesFilledState) {
  // Every large block a fresh mmap (no reuse of resident memory freed earlier):
  // a fixed threshold also stops glibc from raising it after frees.
  // (AddressSanitizer's allocator maps large blocks on its own.)
#ifndef TRISTEREO_TEST_ASAN
  ASSERT_EQ(mallopt(M_MMAP_THRESHOLD, 128 * 1024), 1);
#endif
  constexpr int kW = 2048, kH = 1024;
  // D = 64: the reservation (over 1 GiB at D = 128) must also fit the 32-bit
  // address space of the armhf build.
  PipelineConfig c = config_for(kW, kH, 64, false, 1);
  // The tritree alone, as the pipeline configures it: what its configure() fills.
  std::int64_t tritree_touched = 0, tritree_bytes = 0;
  {
    Tritree tree;
    const std::int64_t rss0 = resident_bytes();
    tree.configure(kW, kH, c.params.tritree);
    tritree_touched = resident_bytes() - rss0;
    tritree_bytes = static_cast<std::int64_t>(tree.working_memory_bytes());
  }
  Pipeline p;
  const std::int64_t rss0 = resident_bytes();
  p.configure(c);
  const std::int64_t touched = resident_bytes() - rss0;
  const auto working = static_cast<std::int64_t>(p.working_memory_bytes());
  // Outside the tritree: the gray copies, the output map and mesh, the
  // reversed right rows and the DP tables, over 50 MiB at this size...
  ASSERT_GT(working - tritree_bytes, 50LL << 20);
  // ...of which configure() faults in almost nothing (the penalty table, the
  // dense-mode sample list, small tables). Under an emulator the resident set
  // is the emulator's, which keeps per-page state for reserved address space
  // (qemu-user: about 0.7 % of it); a buffer filled by mistake is hundreds of
  // MiB here and still far above the bound.
  EXPECT_LT(touched - tritree_touched, (2LL << 20) + working / 50)
      << "configure faulted in " << touched << " bytes, the tritree alone " << tritree_touched
      << "; working memory " << working << ", the tritree's " << tritree_bytes;

  // A 64x48 frame then touches its own share, not the maximum's: the first
  // page of each buffer it writes, which is 2 MiB in the large buffers advised
  // for transparent huge pages (src/memory/large_array.hpp; about eight of
  // them at one worker), still far below one filled buffer here.
  SynthParams sp;
  sp.width = 64;
  sp.height = 48;
  sp.num_disp = 16;
  const SyntheticScene s = make_synthetic_scene(sp);
  const std::int64_t rss1 = resident_bytes();
  p.process(s.left.view(), s.right.view());
  EXPECT_LT(resident_bytes() - rss1, (8LL << 20) + 8 * static_cast<std::int64_t>(kHugePageBytes));
}

}  // namespace
}  // namespace tristereo
