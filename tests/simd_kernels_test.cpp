// Every SIMD kernel set against the scalar kernels, exactly.
//
// Parameterised over each compiled SIMD set (named by set, e.g. .../avx2;
// skipped with a message when this CPU cannot run it). For each kernel: all
// lengths that hit body-only, tail-only and body+tail for 16/32-byte registers,
// every start offset inside a 32-byte register (misaligned pointers), edge
// values, and outputs surrounded by canaries so a write before or past n fails.
// Inputs sit at the very end of their allocation so an over-read is a heap
// overflow under ASan (TRISTEREO_SANITIZE=ON). Then real rows of the
// Middlebury pairs through a box/weighted aggregation and a DP chain.
#include <cstdint>
#include <cstdlib>
#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "src/kernels/dispatch.hpp"
#include "src/kernels/kernel_set.hpp"
#include "support/data.hpp"
#include "support/kernel_param.hpp"
#include "tristereo/io.hpp"
#include "tristereo/status.hpp"

namespace tristereo {
namespace {

constexpr int kSizes[] = {1, 2, 3, 7, 8, 15, 16, 17, 31, 32, 33, 63, 64, 65, 100, 127, 128, 129, 255, 256};
constexpr int kOffsets = 32;  // bytes in the widest register (AVX2)
constexpr int kGuard = 64;    // canary elements on each side of an output
constexpr int kCases = 4;     // value patterns per (n, offset)
constexpr std::uint32_t kMaxPenalty = 32000;
constexpr std::uint32_t kMaxCostQ4 = 4080;
constexpr std::uint32_t kMaxPrev = kMaxCostQ4 + 255 * kMaxPenalty;  // KernelSet::dp_step bound

// An output (or accumulator) with kGuard canaries before and after its n elements.
template <class T>
struct Guarded {
  std::vector<T> buf;
  int n;
  Guarded(const std::vector<T>& init, T canary) : buf(init.size() + 2 * kGuard, canary), n(static_cast<int>(init.size())) {
    std::copy(init.begin(), init.end(), buf.begin() + kGuard);
  }
  T* data() { return buf.data() + kGuard; }
};

// Empty when equal, else where and how the SIMD result differs from the scalar one.
template <class T>
std::string diff(const Guarded<T>& simd, const Guarded<T>& scalar) {
  for (std::size_t i = 0; i < simd.buf.size(); ++i) {
    if (simd.buf[i] != scalar.buf[i]) {
      const long k = static_cast<long>(i) - kGuard;
      return "first difference at element " + std::to_string(k) +
             (k < 0 || k >= simd.n ? " (a canary outside [0, n))" : "") + ": simd " +
             std::to_string(+simd.buf[i]) + ", scalar " + std::to_string(+scalar.buf[i]);
    }
  }
  return {};
}

// An input placed `offset` elements into its allocation, ending exactly at its end.
template <class T>
struct Input {
  std::vector<T> buf;
  int offset;
  Input(const std::vector<T>& values, int off) : buf(values.size() + off), offset(off) {
    std::copy(values.begin(), values.end(), buf.begin() + off);
  }
  const T* data() const { return buf.data() + offset; }
};

// Value patterns: 0 random, 1 all minimum, 2 all maximum, 3 alternating extremes.
template <class T>
std::vector<T> pattern(std::mt19937& rng, int n, int which, T lo, T hi) {
  std::uniform_int_distribution<std::uint64_t> dist(lo, hi);
  std::vector<T> v(n);
  for (int k = 0; k < n; ++k) {
    switch (which % kCases) {
      case 0: v[k] = static_cast<T>(dist(rng)); break;
      case 1: v[k] = lo; break;
      case 2: v[k] = hi; break;
      default: v[k] = (k & 1) ? hi : lo; break;
    }
  }
  return v;
}

template <class T>
std::vector<T> random_values(std::mt19937& rng, int n, std::uint64_t lo, std::uint64_t hi) {
  std::uniform_int_distribution<std::uint64_t> dist(lo, hi);
  std::vector<T> v(n);
  for (T& x : v) x = static_cast<T>(dist(rng));
  return v;
}

class SimdKernels : public ::testing::TestWithParam<KernelChoice> {
 protected:
  void SetUp() override { TRISTEREO_SKIP_UNLESS_RUNNABLE(GetParam()); }
  const KernelSet& simd() const { return kernel_set_for(GetParam()); }
  const KernelSet& scalar() const { return scalar_kernel_set(); }
};

// Calls fn(n, offset, case_index, rng) for every size x offset x value case.
template <class Fn>
void for_each_case(unsigned seed, Fn fn) {
  std::mt19937 rng(seed);
  for (int n : kSizes)
    for (int offset = 0; offset < kOffsets; ++offset)
      for (int c = 0; c < kCases; ++c) fn(n, offset, c, rng);
}

TEST_P(SimdKernels, DispatchGivesTheSetsOwnTable) {
  const KernelSet& s = simd();
  EXPECT_STREQ(s.name, to_string(GetParam()));
  EXPECT_NE(s.accumulate_abs_diff_u16, scalar().accumulate_abs_diff_u16);
  EXPECT_NE(s.accumulate_abs_diff_weighted_u32, scalar().accumulate_abs_diff_weighted_u32);
  EXPECT_NE(s.aggregate_window_box_u16, scalar().aggregate_window_box_u16);
  EXPECT_NE(s.aggregate_window_weighted_u32, scalar().aggregate_window_weighted_u32);
  EXPECT_NE(s.normalize_costs_u16, scalar().normalize_costs_u16);
  EXPECT_NE(s.normalize_costs_u32, scalar().normalize_costs_u32);
  EXPECT_NE(s.normalize_costs_u8, scalar().normalize_costs_u8);
  EXPECT_NE(s.census_costs_row_u8, scalar().census_costs_row_u8);
  EXPECT_NE(s.sum_rows_u8, scalar().sum_rows_u8);
  EXPECT_NE(s.dp_step, scalar().dp_step);
  EXPECT_NE(s.dp_step_u16, scalar().dp_step_u16);
  EXPECT_NE(s.dp_pointer_u16, scalar().dp_pointer_u16);
  EXPECT_NE(s.midpoints_row_q4, scalar().midpoints_row_q4);
  EXPECT_NE(s.midpoints_row_conf_q4, scalar().midpoints_row_conf_q4);
}

TEST_P(SimdKernels, EnvironmentOverridesAuto) {
  const char* old = std::getenv("TRISTEREO_KERNELS");
  const std::string saved = old ? old : "";
  setenv("TRISTEREO_KERNELS", to_string(GetParam()), 1);
  EXPECT_EQ(resolve_kernel_choice(KernelChoice::kAuto), GetParam());
  EXPECT_STREQ(kernel_set_for(KernelChoice::kAuto).name, to_string(GetParam()));
  setenv("TRISTEREO_KERNELS", "scalar", 1);
  EXPECT_EQ(resolve_kernel_choice(KernelChoice::kAuto), KernelChoice::kScalar);
  EXPECT_EQ(resolve_kernel_choice(GetParam()), GetParam());  // explicit beats env
  setenv("TRISTEREO_KERNELS", "sse3", 1);
  EXPECT_THROW(resolve_kernel_choice(KernelChoice::kAuto), Error);
  if (old) setenv("TRISTEREO_KERNELS", saved.c_str(), 1); else unsetenv("TRISTEREO_KERNELS");
}

TEST_P(SimdKernels, AccumulateAbsDiffU16) {
  const std::uint8_t lefts[] = {0, 255, 77, 128};
  const std::uint8_t truncs[] = {255, 1, 255, 30};
  for_each_case(1, [&](int n, int offset, int c, std::mt19937& rng) {
    const Input<std::uint8_t> right(pattern<std::uint8_t>(rng, n, c, 0, 255), offset);
    // Any start value: both sides wrap mod 2^16 the same way.
    const std::vector<std::uint16_t> acc0 = random_values<std::uint16_t>(rng, n, 0, 0xffff);
    const std::uint8_t left = lefts[(c + offset) % 4];
    const std::uint8_t trunc = truncs[(c + n) % 4];
    Guarded<std::uint16_t> a(acc0, 0xA5A5), b(acc0, 0xA5A5);
    simd().accumulate_abs_diff_u16(right.data(), left, trunc, n, a.data());
    scalar().accumulate_abs_diff_u16(right.data(), left, trunc, n, b.data());
    ASSERT_EQ(diff(a, b), "") << "n=" << n << " offset=" << offset << " case=" << c
                              << " left=" << +left << " trunc=" << +trunc;
  });
}

TEST_P(SimdKernels, AccumulateAbsDiffWeightedU32) {
  // 0..255 is the model's range; 256/257 are the last weights whose product
  // fits 16 bits; 1000 and 65535 take the kernel's scalar fallback.
  const std::uint16_t weights[] = {255, 1, 0, 173, 256, 257, 1000, 65535};
  const std::uint8_t truncs[] = {255, 1, 200, 17};
  for_each_case(2, [&](int n, int offset, int c, std::mt19937& rng) {
    const Input<std::uint8_t> right(pattern<std::uint8_t>(rng, n, c, 0, 255), offset);
    const std::vector<std::uint32_t> acc0 = random_values<std::uint32_t>(rng, n, 0, 0xffffffffu);
    const std::uint8_t left = static_cast<std::uint8_t>(c == 1 ? 255 : rng() & 0xff);
    const std::uint16_t weight = weights[(c + offset) % 8];
    const std::uint8_t trunc = truncs[(n + offset) % 4];
    Guarded<std::uint32_t> a(acc0, 0xDEADBEEF), b(acc0, 0xDEADBEEF);
    simd().accumulate_abs_diff_weighted_u32(right.data(), left, weight, trunc, n, a.data());
    scalar().accumulate_abs_diff_weighted_u32(right.data(), left, weight, trunc, n, b.data());
    ASSERT_EQ(diff(a, b), "") << "n=" << n << " offset=" << offset << " case=" << c
                              << " left=" << +left << " weight=" << weight << " trunc=" << +trunc;
  });
}

// ---------------------------------------------------------------- window kernels

// Window sizes: 1 pixel, around the u8 group sizes of small truncations, the
// default 5x5, and the largest 31x31.
constexpr int kWindowCounts[] = {1, 2, 7, 8, 9, 25, 49, 255, 256, 961};
// 255 / trunc is the number of pixels summed in u8 before widening: 1, 2, 8,
// 3, 2, 1 and 255 pixels; 255 and 128 make every group a single pixel.
constexpr std::uint8_t kWindowTruncs[] = {255, 128, 30, 85, 127, 1, 254};

// `count` window pixels whose right runs of n bytes start at arbitrary
// (misaligned) offsets of one buffer; the last run ends exactly at the end of
// the allocation, so an over-read past n trips ASan.
struct WindowInput {
  std::vector<std::uint8_t> buf;
  std::vector<const std::uint8_t*> right;
  std::vector<std::uint8_t> left;
  WindowInput(std::mt19937& rng, int count, int n, int which) {
    const int span = n + 64;
    buf.resize(static_cast<std::size_t>(count) * span);
    const std::vector<std::uint8_t> values = pattern<std::uint8_t>(rng, static_cast<int>(buf.size()), which, 0, 255);
    std::copy(values.begin(), values.end(), buf.begin());
    for (int i = 0; i < count; ++i) {
      const int off = i == count - 1 ? span - n : static_cast<int>(rng() % (span - n + 1));
      right.push_back(buf.data() + static_cast<std::size_t>(i) * span + off);
      left.push_back(which % kCases == 1 ? 255 : static_cast<std::uint8_t>(rng()));
    }
  }
};

TEST_P(SimdKernels, AggregateWindowBoxU16) {
  std::mt19937 rng(11);
  for (int n : kSizes) {
    for (int count : kWindowCounts) {
      for (int c = 0; c < kCases; ++c) {
        const WindowInput in(rng, count, n, c);
        const std::uint8_t trunc = kWindowTruncs[(n + count + c) % 7];
        // Outputs start at a different misalignment per case; the kernel
        // overwrites them, so the initial content must not matter.
        Guarded<std::uint16_t> a(random_values<std::uint16_t>(rng, n, 0, 0xffff), 0xA5A5);
        Guarded<std::uint16_t> b(std::vector<std::uint16_t>(n, 0x1234), 0xA5A5);
        simd().aggregate_window_box_u16(in.right.data(), in.left.data(), count, trunc, n, a.data());
        scalar().aggregate_window_box_u16(in.right.data(), in.left.data(), count, trunc, n, b.data());
        ASSERT_EQ(diff(a, b), "") << "n=" << n << " count=" << count << " case=" << c
                                  << " trunc=" << +trunc;
      }
    }
  }
}

TEST_P(SimdKernels, AggregateWindowBoxU16EveryTruncation) {
  // Every T_c with the default window and with a window of exactly one
  // 255 / T_c group plus one pixel (the first widening happens mid-window).
  std::mt19937 rng(12);
  for (int t = 1; t <= 255; ++t) {
    for (int count : {25, 255 / t + 1}) {
      for (int n : {16, 64, 100}) {
        const WindowInput in(rng, count, n, t);
        const auto trunc = static_cast<std::uint8_t>(t);
        Guarded<std::uint16_t> a(std::vector<std::uint16_t>(n, 0), 0xA5A5), b = a;
        simd().aggregate_window_box_u16(in.right.data(), in.left.data(), count, trunc, n, a.data());
        scalar().aggregate_window_box_u16(in.right.data(), in.left.data(), count, trunc, n, b.data());
        ASSERT_EQ(diff(a, b), "") << "n=" << n << " count=" << count << " trunc=" << t;
      }
    }
  }
}

TEST_P(SimdKernels, AggregateWindowWeightedU32) {
  std::mt19937 rng(13);
  for (int n : kSizes) {
    for (int count : kWindowCounts) {
      for (int c = 0; c < kCases + 1; ++c) {
        const WindowInput in(rng, count, n, c);
        const std::uint8_t trunc = kWindowTruncs[(n + count + c) % 7];
        // Model weights 0..254 (0 included: the kernel must add nothing for
        // it), 1 for large boxes, 256/257 (largest with a 16-bit product);
        // case kCases puts one weight above 257 in: the whole call falls back.
        std::vector<std::uint16_t> weight(count);
        for (auto& w : weight) {
          switch (c) {
            case 0: w = static_cast<std::uint16_t>(rng() % 255); break;
            case 1: w = 254; break;
            case 2: w = 1; break;
            case 3: w = static_cast<std::uint16_t>(rng() % 258); break;
            default: w = static_cast<std::uint16_t>(rng() % 256); break;
          }
        }
        if (c == kCases) weight[rng() % count] = static_cast<std::uint16_t>(258 + rng() % 65278);
        Guarded<std::uint32_t> a(random_values<std::uint32_t>(rng, n, 0, 0xffffffffu), 0xDEADBEEF);
        Guarded<std::uint32_t> b(std::vector<std::uint32_t>(n, 7), 0xDEADBEEF);
        simd().aggregate_window_weighted_u32(in.right.data(), in.left.data(), weight.data(), count,
                                             trunc, n, a.data());
        scalar().aggregate_window_weighted_u32(in.right.data(), in.left.data(), weight.data(), count,
                                               trunc, n, b.data());
        ASSERT_EQ(diff(a, b), "") << "n=" << n << " count=" << count << " case=" << c
                                  << " trunc=" << +trunc;
      }
    }
  }
}

TEST_P(SimdKernels, AggregateWindowKnownSums) {
  // Ground truth without the scalar kernel: every pixel differs from every
  // right value by exactly 3 (left 10, right 13), so box sums are 3 * count
  // (or T_c * count when T_c < 3) and weighted sums 3 * (sum of weights).
  for (int n : {1, 15, 17, 33, 256}) {
    for (int count : {1, 25, 961}) {
      std::vector<std::uint8_t> row(static_cast<std::size_t>(n) + 31, 13);
      std::vector<const std::uint8_t*> right(count);
      std::vector<std::uint8_t> left(count, 10);
      std::vector<std::uint16_t> weight(count);
      std::uint32_t total = 0;
      for (int i = 0; i < count; ++i) {
        right[i] = row.data() + i % 31;
        weight[i] = static_cast<std::uint16_t>(i % 255);
        total += weight[i];
      }
      for (std::uint8_t trunc : {std::uint8_t{2}, std::uint8_t{30}}) {
        std::vector<std::uint16_t> box(n, 0xffff);
        std::vector<std::uint32_t> wsum(n, 0xffffffffu);
        simd().aggregate_window_box_u16(right.data(), left.data(), count, trunc, n, box.data());
        simd().aggregate_window_weighted_u32(right.data(), left.data(), weight.data(), count, trunc,
                                             n, wsum.data());
        const std::uint32_t diff_value = trunc < 3 ? trunc : 3;
        for (int k = 0; k < n; ++k) {
          ASSERT_EQ(box[k], diff_value * count) << "n=" << n << " count=" << count << " k=" << k;
          ASSERT_EQ(wsum[k], diff_value * total) << "n=" << n << " count=" << count << " k=" << k;
        }
      }
    }
  }
}

// inv_q32 = floor(2^32 / W) for the model's weight sums, plus arbitrary 64-bit
// values: the SIMD kernels reproduce the scalar 64-bit expression for any input.
std::uint64_t pick_inv(std::mt19937& rng, int which) {
  constexpr std::uint64_t kTwo32 = std::uint64_t{1} << 32;
  switch (which % 6) {
    case 0: return kTwo32;                                     // W = 1 (1x1 box)
    case 1: return kTwo32 / (31 * 31);                         // largest box window
    case 2: return kTwo32 / (31 * 31 * 255);                   // largest weight sum
    case 3: return kTwo32 / (1 + rng() % (31 * 31 * 255));     // any model W
    case 4: return (std::uint64_t{rng()} << 32) | rng();       // arbitrary
    default: return kTwo32 - 1 - (rng() & 0xffff);             // just below 2^32
  }
}

TEST_P(SimdKernels, RgbToGrayRowU8) {
  for_each_case(21, [&](int n, int offset, int c, std::mt19937& rng) {
    const Input<std::uint8_t> rgb(pattern<std::uint8_t>(rng, 3 * n, c, 0, 255), offset);
    Guarded<std::uint8_t> a(std::vector<std::uint8_t>(n, 0x5A), 0x5A);
    Guarded<std::uint8_t> b = a;
    simd().rgb_to_gray_row_u8(rgb.data(), n, a.data());
    scalar().rgb_to_gray_row_u8(rgb.data(), n, b.data());
    ASSERT_EQ(diff(a, b), "") << "n=" << n << " offset=" << offset;
  });
  // Every value of each channel with the others at random, and real rows.
  std::mt19937 rng(22);
  std::vector<std::uint8_t> rgb(3 * 256 * 3);
  for (int ch = 0; ch < 3; ++ch)
    for (int v = 0; v < 256; ++v)
      for (int k = 0; k < 3; ++k)
        rgb[static_cast<std::size_t>(3 * (256 * ch + v) + k)] = k == ch ? static_cast<std::uint8_t>(v) : static_cast<std::uint8_t>(rng());
  std::vector<std::uint8_t> a(768), b(768);
  simd().rgb_to_gray_row_u8(rgb.data(), 768, a.data());
  scalar().rgb_to_gray_row_u8(rgb.data(), 768, b.data());
  EXPECT_EQ(a, b);
  if (!test::data_set_available("middlebury")) {
    TRISTEREO_REQUIRE_DATA("middlebury");
    return;
  }
  const ImageU8 img = read_image_u8(test::data_set_dir("middlebury") + "/teddy/left.png");
  ASSERT_EQ(img.channels, 3);
  std::vector<std::uint8_t> ga(static_cast<std::size_t>(img.width)), gb(ga.size());
  for (int y = 0; y < img.height; ++y) {
    simd().rgb_to_gray_row_u8(img.row(y), img.width, ga.data());
    scalar().rgb_to_gray_row_u8(img.row(y), img.width, gb.data());
    ASSERT_EQ(ga, gb) << "teddy row " << y;
  }
}

TEST_P(SimdKernels, BgrToGrayRowU8) {
  for_each_case(23, [&](int n, int offset, int c, std::mt19937& rng) {
    const Input<std::uint8_t> bgr(pattern<std::uint8_t>(rng, 3 * n, c, 0, 255), offset);
    Guarded<std::uint8_t> a(std::vector<std::uint8_t>(n, 0x5A), 0x5A);
    Guarded<std::uint8_t> b = a;
    simd().bgr_to_gray_row_u8(bgr.data(), n, a.data());
    scalar().bgr_to_gray_row_u8(bgr.data(), n, b.data());
    ASSERT_EQ(diff(a, b), "") << "n=" << n << " offset=" << offset;
  });
  // Every value of each channel with the others at random: the BGR row is the
  // RGB row of the reversed triplets, in this set and in the scalar one.
  std::mt19937 rng(24);
  std::vector<std::uint8_t> rgb(3 * 256 * 3), bgr(rgb.size());
  for (int ch = 0; ch < 3; ++ch)
    for (int v = 0; v < 256; ++v)
      for (int k = 0; k < 3; ++k)
        rgb[static_cast<std::size_t>(3 * (256 * ch + v) + k)] = k == ch ? static_cast<std::uint8_t>(v) : static_cast<std::uint8_t>(rng());
  for (std::size_t i = 0; i < rgb.size(); i += 3)
    for (int k = 0; k < 3; ++k) bgr[i + 2 - k] = rgb[i + k];
  std::vector<std::uint8_t> a(768), b(768);
  simd().bgr_to_gray_row_u8(bgr.data(), 768, a.data());
  scalar().rgb_to_gray_row_u8(rgb.data(), 768, b.data());
  EXPECT_EQ(a, b);
}

TEST_P(SimdKernels, NormalizeCostsU16) {
  for_each_case(3, [&](int n, int offset, int c, std::mt19937& rng) {
    const Input<std::uint16_t> sum(pattern<std::uint16_t>(rng, n, c, 0, 0xffff), offset);
    const std::uint64_t inv = pick_inv(rng, c + offset);
    Guarded<std::uint16_t> a(std::vector<std::uint16_t>(n, 0x5A5A), 0x5A5A);
    Guarded<std::uint16_t> b = a;
    simd().normalize_costs_u16(sum.data(), inv, n, a.data());
    scalar().normalize_costs_u16(sum.data(), inv, n, b.data());
    ASSERT_EQ(diff(a, b), "") << "n=" << n << " offset=" << offset << " inv=" << inv;
  });
}

TEST_P(SimdKernels, NormalizeCostsU8) {
  for_each_case(5, [&](int n, int offset, int c, std::mt19937& rng) {
    const Input<std::uint8_t> sum(pattern<std::uint8_t>(rng, n, c, 0, 0xff), offset);
    const std::uint64_t inv = pick_inv(rng, c + offset);
    Guarded<std::uint16_t> a(std::vector<std::uint16_t>(n, 0x5A5A), 0x5A5A);
    Guarded<std::uint16_t> b = a, wide_out = a;
    simd().normalize_costs_u8(sum.data(), inv, n, a.data());
    scalar().normalize_costs_u8(sum.data(), inv, n, b.data());
    ASSERT_EQ(diff(a, b), "") << "n=" << n << " offset=" << offset << " inv=" << inv;
    // The scalar twin is normalize_costs_u16 of the widened sums.
    std::vector<std::uint16_t> wide(sum.data(), sum.data() + n);
    scalar().normalize_costs_u16(wide.data(), inv, n, wide_out.data());
    ASSERT_EQ(diff(b, wide_out), "") << "n=" << n;
  });
}

TEST_P(SimdKernels, NormalizeCostsU32) {
  for_each_case(4, [&](int n, int offset, int c, std::mt19937& rng) {
    // Model sums are < 2^28; the kernel is exact for every u32 anyway.
    const std::uint32_t hi = (offset & 1) ? 0xffffffffu : (1u << 28) - 1;
    const Input<std::uint32_t> sum(pattern<std::uint32_t>(rng, n, c, 0, hi), offset);
    const std::uint64_t inv = pick_inv(rng, c + offset);
    Guarded<std::uint16_t> a(std::vector<std::uint16_t>(n, 0x5A5A), 0x5A5A);
    Guarded<std::uint16_t> b = a;
    simd().normalize_costs_u32(sum.data(), inv, n, a.data());
    scalar().normalize_costs_u32(sum.data(), inv, n, b.data());
    ASSERT_EQ(diff(a, b), "") << "n=" << n << " offset=" << offset << " inv=" << inv;
  });
}

TEST_P(SimdKernels, NormalizeRealWeightSumsIsTheMeanInQ4) {
  // Known answer through the SIMD kernel: sum = W * c gives exactly 16 c.
  const int weight_sums[] = {1, 9, 25, 254, 961, 961 * 255};
  for (int w : weight_sums) {
    const std::uint64_t inv = (std::uint64_t{1} << 32) / static_cast<std::uint64_t>(w);
    std::vector<std::uint32_t> sum(256);
    for (int c = 0; c < 256; ++c) sum[c] = static_cast<std::uint32_t>(w) * static_cast<std::uint32_t>(c % 256);
    std::vector<std::uint16_t> cost(256);
    simd().normalize_costs_u32(sum.data(), inv, 256, cost.data());
    for (int c = 0; c < 256; ++c) ASSERT_EQ(cost[c], 16 * c) << "W=" << w << " c=" << c;
  }
}

// prev patterns for the DP: random over the whole bound, ties, extremes,
// and a descending ramp (every lane's best j is far to the right).
std::vector<std::uint32_t> dp_prev(std::mt19937& rng, int n, int which) {
  std::vector<std::uint32_t> v(n);
  for (int k = 0; k < n; ++k) {
    switch (which % 6) {
      case 0: v[k] = static_cast<std::uint32_t>(rng() % (kMaxPrev + 1)); break;
      case 1: v[k] = 0; break;
      case 2: v[k] = kMaxPrev; break;
      case 3: v[k] = static_cast<std::uint32_t>(rng() % 4); break;  // many equal values
      case 4: v[k] = static_cast<std::uint32_t>((n - k) * 31); break;
      default: v[k] = (k & 1) ? kMaxPrev : static_cast<std::uint32_t>(rng() % 50); break;
    }
  }
  return v;
}

TEST_P(SimdKernels, DpStep) {
  const std::uint32_t penalties[] = {0, kMaxPenalty, 1, 7, 255, 4096};
  std::mt19937 rng(5);
  for (int n : kSizes) {
    for (int offset = 0; offset < kOffsets; ++offset) {
      for (int c = 0; c < 6; ++c) {
        const Input<std::uint32_t> prev(dp_prev(rng, n, c + offset), offset);
        const Input<std::uint16_t> cost(
            pattern<std::uint16_t>(rng, n, c, 0, static_cast<std::uint16_t>(kMaxCostQ4)), offset);
        const std::uint32_t penalty = (c + offset) % 7 == 6
                                          ? static_cast<std::uint32_t>(rng() % (kMaxPenalty + 1))
                                          : penalties[(c + offset) % 6];
        Guarded<std::uint32_t> out_a(std::vector<std::uint32_t>(n, 0xCAFEF00D), 0xCAFEF00D);
        Guarded<std::uint32_t> out_b = out_a;
        Guarded<std::uint8_t> ptr_a(std::vector<std::uint8_t>(n, 0xEE), 0xEE);
        Guarded<std::uint8_t> ptr_b = ptr_a;
        simd().dp_step(cost.data(), prev.data(), penalty, n, out_a.data(), ptr_a.data());
        scalar().dp_step(cost.data(), prev.data(), penalty, n, out_b.data(), ptr_b.data());
        ASSERT_EQ(diff(out_a, out_b), "") << "out: n=" << n << " offset=" << offset
                                          << " case=" << c << " penalty=" << penalty;
        ASSERT_EQ(diff(ptr_a, ptr_b), "") << "ptr: n=" << n << " offset=" << offset
                                          << " case=" << c << " penalty=" << penalty;
      }
    }
  }
}

// u16 DP prev patterns: random up to the u16 bound of `penalty`, all 0xFFFF,
// ties, a descending ramp, and extremes alternating.
std::vector<std::uint16_t> dp_prev_u16(std::mt19937& rng, int n, int which, std::uint32_t penalty) {
  const std::uint32_t bound = std::min<std::uint32_t>(0xFFFF, kMaxCostQ4 + 255 * penalty);
  std::vector<std::uint16_t> v(n);
  for (int k = 0; k < n; ++k) {
    std::uint32_t x;
    switch (which % 6) {
      case 0: x = rng() % (bound + 1); break;
      case 1: x = 0xFFFF; break;  // every term saturates in the pointer search
      case 2: x = bound; break;
      case 3: x = rng() % 4; break;
      case 4: x = static_cast<std::uint32_t>((n - k) * 31); break;
      default: x = (k & 1) ? bound : rng() % 50; break;
    }
    v[k] = static_cast<std::uint16_t>(x);
  }
  return v;
}

// Penalties around the u16 path's limit (241 = kMaxDpPenaltyU16: 4080 + 255 * 241
// = 65535), the pointer kernel's 16-bit product limit (257 / 258), and far
// beyond (the kernels are exact for any penalty; saturated ramps).
constexpr std::uint32_t kU16Penalties[] = {0, 1, 40, 240, 241, 257, 258, 4095, 4096, 65535, 100000};

TEST_P(SimdKernels, DpStepU16) {
  std::mt19937 rng(6);
  for (int n : kSizes) {
    for (int offset = 0; offset < kOffsets; ++offset) {
      for (int c = 0; c < 6; ++c) {
        const std::uint32_t penalty = kU16Penalties[(c + offset) % 11];
        const Input<std::uint16_t> prev(dp_prev_u16(rng, n, c + offset, penalty), offset);
        const Input<std::uint16_t> cost(
            pattern<std::uint16_t>(rng, n, c, 0, static_cast<std::uint16_t>(kMaxCostQ4)), offset);
        Guarded<std::uint16_t> out_a(std::vector<std::uint16_t>(n, 0xF00D), 0xF00D);
        Guarded<std::uint16_t> out_b = out_a;
        simd().dp_step_u16(cost.data(), prev.data(), penalty, n, out_a.data());
        scalar().dp_step_u16(cost.data(), prev.data(), penalty, n, out_b.data());
        ASSERT_EQ(diff(out_a, out_b), "") << "n=" << n << " offset=" << offset << " case=" << c
                                          << " penalty=" << penalty;
      }
    }
  }
}

TEST_P(SimdKernels, DpStepU16AtTheBoundEdge) {
  // penalty 241, cost 4080 and prev with g - min g = 255 * 241: out reaches
  // exactly 65535 (the largest value the u16 path must hold) without wrapping.
  for (int n : {2, 17, 64, 256}) {
    std::vector<std::uint16_t> prev(n, 0xFFFF), cost(n, 4080), out_a(n), out_b(n);
    prev[0] = 0;
    simd().dp_step_u16(cost.data(), prev.data(), kMaxDpPenaltyU16, n, out_a.data());
    scalar().dp_step_u16(cost.data(), prev.data(), kMaxDpPenaltyU16, n, out_b.data());
    ASSERT_EQ(out_a, out_b) << "n=" << n;
    EXPECT_EQ(out_a[0], 4080);
    EXPECT_EQ(out_a[n - 1], 4080 + (n - 1) * kMaxDpPenaltyU16) << "n=" << n;
  }
}

TEST_P(SimdKernels, DpPointerU16EveryK) {
  std::mt19937 rng(8);
  for (int n : kSizes) {
    for (int offset = 0; offset < kOffsets; offset += 3) {
      for (int c = 0; c < 6; ++c) {
        const std::uint32_t penalty = kU16Penalties[(c + offset) % 11];
        const Input<std::uint16_t> prev(dp_prev_u16(rng, n, c + offset, penalty), offset);
        for (int k = 0; k < n; ++k)
          ASSERT_EQ(simd().dp_pointer_u16(prev.data(), penalty, n, k),
                    scalar().dp_pointer_u16(prev.data(), penalty, n, k))
              << "n=" << n << " offset=" << offset << " case=" << c << " penalty=" << penalty
              << " k=" << k;
      }
    }
  }
}

// ---------------------------------------------------------------- Middlebury rows

// Gray by the model's BT.601 Q8 rule (docs/model.md section 0).
std::vector<std::uint8_t> gray_of(const ImageU8& img) {
  std::vector<std::uint8_t> g(static_cast<std::size_t>(img.width) * img.height);
  for (int y = 0; y < img.height; ++y) {
    const std::uint8_t* row = img.row(y);
    for (int x = 0; x < img.width; ++x) {
      const std::uint8_t* p = row + x * img.channels;
      g[static_cast<std::size_t>(y) * img.width + x] =
          img.channels >= 3 ? static_cast<std::uint8_t>((77 * p[0] + 150 * p[1] + 29 * p[2] + 128) >> 8)
                            : p[0];
    }
  }
  return g;
}

TEST_P(SimdKernels, MiddleburyRowsThroughAggregationAndDp) {
  TRISTEREO_REQUIRE_MIDDLEBURY();
  const char* kSets[] = {"tsukuba", "venus", "teddy", "cones"};
  constexpr int kHalf = 2;  // 5x5 window
  for (const char* name : kSets) {
    const std::string dir = test::data_set_dir("middlebury") + "/" + name;
    const ImageU8 left_img = read_image_u8(dir + "/left.png");
    const ImageU8 right_img = read_image_u8(dir + "/right.png");
    const int w = left_img.width, h = left_img.height;
    const std::vector<std::uint8_t> L = gray_of(left_img), R = gray_of(right_img);
    auto at = [w, h](const std::vector<std::uint8_t>& img, int x, int y) {
      x = x < 0 ? 0 : (x >= w ? w - 1 : x);
      y = y < 0 ? 0 : (y >= h ? h - 1 : y);
      return img[static_cast<std::size_t>(y) * w + x];
    };
    for (int d_count : {16, 61, 64}) {
      for (int y : {h / 4, h / 2, (3 * h) / 4}) {
        std::vector<std::uint32_t> prev_a(d_count), prev_b(d_count);
        std::vector<std::uint8_t> right_rev(d_count);
        for (int x = 0; x < w; ++x) {
          std::vector<std::uint16_t> box_a(d_count, 0), box_b(d_count, 0);
          std::vector<std::uint32_t> wsum_a(d_count, 0), wsum_b(d_count, 0);
          std::uint32_t weight_total = 0;
          for (int dy = -kHalf; dy <= kHalf; ++dy) {
            for (int dx = -kHalf; dx <= kHalf; ++dx) {
              const std::uint8_t l = at(L, x + dx, y + dy);
              for (int k = 0; k < d_count; ++k) right_rev[k] = at(R, x + dx - k, y + dy);
              // A similarity-style weight in 0..255 from the left image.
              const int t = l > at(L, x, y) ? l - at(L, x, y) : at(L, x, y) - l;
              const std::uint16_t weight = static_cast<std::uint16_t>(255 - (t > 255 ? 255 : t));
              weight_total += weight;
              simd().accumulate_abs_diff_u16(right_rev.data(), l, 40, d_count, box_a.data());
              scalar().accumulate_abs_diff_u16(right_rev.data(), l, 40, d_count, box_b.data());
              simd().accumulate_abs_diff_weighted_u32(right_rev.data(), l, weight, 255, d_count, wsum_a.data());
              scalar().accumulate_abs_diff_weighted_u32(right_rev.data(), l, weight, 255, d_count, wsum_b.data());
            }
          }
          ASSERT_EQ(box_a, box_b) << name << " y=" << y << " x=" << x << " D=" << d_count;
          ASSERT_EQ(wsum_a, wsum_b) << name << " y=" << y << " x=" << x << " D=" << d_count;
          std::vector<std::uint16_t> cost_a(d_count), cost_b(d_count), cost_w_a(d_count), cost_w_b(d_count);
          const std::uint64_t inv_box = (std::uint64_t{1} << 32) / 25;
          const std::uint64_t inv_w = (std::uint64_t{1} << 32) / (weight_total ? weight_total : 1);
          simd().normalize_costs_u16(box_a.data(), inv_box, d_count, cost_a.data());
          scalar().normalize_costs_u16(box_b.data(), inv_box, d_count, cost_b.data());
          simd().normalize_costs_u32(wsum_a.data(), inv_w, d_count, cost_w_a.data());
          scalar().normalize_costs_u32(wsum_b.data(), inv_w, d_count, cost_w_b.data());
          ASSERT_EQ(cost_a, cost_b) << name << " y=" << y << " x=" << x;
          ASSERT_EQ(cost_w_a, cost_w_b) << name << " y=" << y << " x=" << x;
          // DP along the row (dense mode), box costs, penalty 400 in Q4 units.
          std::vector<std::uint32_t> out_a(d_count), out_b(d_count);
          std::vector<std::uint8_t> ptr_a(d_count), ptr_b(d_count);
          if (x == 0) {
            for (int k = 0; k < d_count; ++k) prev_a[k] = prev_b[k] = cost_b[k];
            continue;
          }
          simd().dp_step(cost_a.data(), prev_a.data(), 400, d_count, out_a.data(), ptr_a.data());
          scalar().dp_step(cost_b.data(), prev_b.data(), 400, d_count, out_b.data(), ptr_b.data());
          ASSERT_EQ(out_a, out_b) << name << " y=" << y << " x=" << x << " D=" << d_count;
          ASSERT_EQ(ptr_a, ptr_b) << name << " y=" << y << " x=" << x << " D=" << d_count;
          prev_a = out_a;
          prev_b = out_b;
        }
      }
    }
  }
}

// Pixel rows for the tritree kernels' cases: c = 0 random, 1 flat dark, 2
// flat bright, 3 a checkerboard, 4 bright lines every 8 columns and 4 rows
// (the squares' corners against their insides), 5 a ramp with noise.
std::vector<std::vector<std::uint8_t>> case_rows(int c, int rows, int width, std::mt19937& rng) {
  std::vector<std::vector<std::uint8_t>> px(static_cast<std::size_t>(rows),
                                            std::vector<std::uint8_t>(static_cast<std::size_t>(width)));
  for (int r = 0; r < rows; ++r)
    for (int x = 0; x < width; ++x) {
      std::uint8_t& v = px[static_cast<std::size_t>(r)][static_cast<std::size_t>(x)];
      switch (c) {
        case 0: v = static_cast<std::uint8_t>(rng()); break;
        case 1: v = 0; break;
        case 2: v = 255; break;
        case 3: v = ((x + r) & 1) ? 255 : 0; break;
        case 4: v = (x % 8 == 0 || r % 4 == 0) ? 255 : 0; break;
        default: v = static_cast<std::uint8_t>(std::clamp(3 * x + 5 * r + static_cast<int>(rng() % 9), 0, 255));
      }
    }
  return px;
}

// Teddy's left view as gray (the scalar conversion); *img gets the colour image.
std::vector<std::uint8_t> teddy_gray(ImageU8* img) {
  *img = read_image_u8(test::data_set_dir("middlebury") + "/teddy/left.png");
  std::vector<std::uint8_t> gray(static_cast<std::size_t>(img->width) * img->height);
  for (int y = 0; y < img->height; ++y)
    scalar_kernel_set().rgb_to_gray_row_u8(img->row(y), img->width,
                                           gray.data() + static_cast<std::size_t>(y) * img->width);
  return gray;
}

// A square kernel's inputs (side 4 or 8): n = 1 .. max_n squares of every
// case_rows() case, both first diagonals and the four limit regimes (random
// cases take all four, the others the smooth one instead of the random one),
// then every `side`-row band of Teddy with `teddy_limit`. run(rows, n,
// first_backslash, limits, what) checks one input. False when the test is
// over (a fatal failure, or no Middlebury data: skipped or failed).
template <class Limit, class Run, class Limits>
bool drive_square_kernel(int side, int max_n, std::mt19937& rng, Run run, Limits limits,
                         const std::vector<Limit>& teddy_limit) {
  for (int n = 1; n <= max_n; ++n) {
    for (int c = 0; c < 6; ++c) {
      const auto px = case_rows(c, side + 1, side * n + 1, rng);
      for (int first_bs = 0; first_bs < 2; ++first_bs)
        for (int which = 0; which < 4; ++which) {
          run(px, n, first_bs, limits(c == 0 ? which : (which == 0 ? 1 : which)), "case " + std::to_string(c));
          if (::testing::Test::HasFatalFailure()) return false;
        }
    }
  }
  if (!test::data_set_available("middlebury")) {
    [] { TRISTEREO_REQUIRE_DATA("middlebury"); }();
    return false;
  }
  ImageU8 img;
  const std::vector<std::uint8_t> gray = teddy_gray(&img);
  const int n = (img.width - 1) / side;
  for (int y = 0; y + side < img.height; y += side) {
    std::vector<std::vector<std::uint8_t>> px;
    for (int r = 0; r <= side; ++r) {
      const std::uint8_t* row = gray.data() + static_cast<std::size_t>(y + r) * img.width;
      px.emplace_back(row, row + side * n + 1);
    }
    run(px, n, (y / side) & 1, teddy_limit, "teddy y=" + std::to_string(y));
    if (::testing::Test::HasFatalFailure()) return false;
  }
  return true;
}

// The tritree's side-4 level: n squares side by side, each row of pixels from
// its own allocation ending right after the last square's right corner (an
// over-read is a heap overflow under ASan); limits spread over the SSEs'
// range so that every bit takes both values.
TEST_P(SimdKernels, Side4TestsU8) {
  std::mt19937 rng(23);
  std::uint32_t ones = 0, zeros = 0;  // wants bits seen set and clear (scalar)
  const auto run = [&](const std::vector<std::vector<std::uint8_t>>& pixel_rows, int n, int first_bs,
                       const std::vector<std::int32_t>& limit, const std::string& what) {
    std::vector<Input<std::uint8_t>> in;
    const std::uint8_t* rows[5];
    for (int r = 0; r < 5; ++r) in.emplace_back(pixel_rows[static_cast<std::size_t>(r)], 0);
    for (int r = 0; r < 5; ++r) rows[r] = in[static_cast<std::size_t>(r)].data();
    Guarded<std::uint32_t> wa(std::vector<std::uint32_t>(static_cast<std::size_t>(n), 0xA5A5A5A5u), 0xA5A5A5A5u);
    Guarded<std::uint32_t> wb = wa;
    const std::size_t stride = static_cast<std::size_t>(n) + 3;
    Guarded<std::int32_t> sa(std::vector<std::int32_t>(8 * stride, -7), -7);
    Guarded<std::int32_t> sb = sa;
    simd().side4_tests_u8(rows, n, first_bs, limit.data(), wa.data(), sa.data(), stride);
    scalar().side4_tests_u8(rows, n, first_bs, limit.data(), wb.data(), sb.data(), stride);
    ASSERT_EQ(diff(wa, wb), "") << what << " n=" << n << " first_backslash=" << first_bs;
    ASSERT_EQ(diff(sa, sb), "") << what << " n=" << n << " first_backslash=" << first_bs;
    for (int m = 0; m < n; ++m) ones |= wb.data()[m], zeros |= ~wb.data()[m];
  };
  const auto limits = [&](int which) {
    std::vector<std::int32_t> l(8);
    for (std::int32_t& v : l) {
      switch (which) {
        case 0: v = static_cast<std::int32_t>(rng() % 200000); break;   // mixed on random pixels
        case 1: v = static_cast<std::int32_t>(rng() % 2000); break;     // mixed on smooth pixels
        case 2: v = 0; break;                                           // any residual fails
        default: v = INT32_MAX; break;                                  // never
      }
    }
    return l;
  };
  if (!drive_square_kernel(4, 40, rng, run, limits,
                           std::vector<std::int32_t>{20000, 20000, 20000, 20000, 60000, 60000, 60000, 60000}))
    return;
  EXPECT_EQ(ones & 0x3Fu, 0x3Fu) << "some wants bit was never set";
  EXPECT_EQ(zeros & 0x3Fu, 0x3Fu) << "some wants bit was never clear";
}

// The tritree's side-8 level: n squares side by side, fed with the side-4
// level's sums of the same pixels (as the tritree feeds it: the double-lane
// twins are exact for those magnitudes), each pixel row and sum plane in its
// own allocation ending where the kernel's reads must end (ASan).
TEST_P(SimdKernels, Side8TestsS32) {
  std::mt19937 rng(29);
  std::uint32_t ones = 0, zeros = 0;  // wants bits seen set and clear (scalar)
  const auto run = [&](const std::vector<std::vector<std::uint8_t>>& pixel_rows, int n, int first_bs,
                       const std::vector<std::int64_t>& limit, const std::string& what) {
    // Rows 0 .. 8 of the row of squares: the side-4 sums of its two rows of 4 x 4 squares.
    const std::size_t stride4 = static_cast<std::size_t>(2 * n) + 1;
    std::vector<std::vector<std::int32_t>> quad(2, std::vector<std::int32_t>(8 * stride4 - 1));
    for (int dy = 0; dy < 2; ++dy) {
      const std::uint8_t* rows4[5];
      for (int r = 0; r < 5; ++r) rows4[r] = pixel_rows[static_cast<std::size_t>(4 * dy + r)].data();
      std::vector<std::uint32_t> wants4(static_cast<std::size_t>(2 * n));
      const std::int32_t never[8] = {INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX,
                                     INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX};
      // a quadrant on the 8 x 8 square's diagonal is '\\', whatever the square's own
      scalar().side4_tests_u8(rows4, 2 * n, dy == 0 ? 1 : 0, never, wants4.data(),
                              quad[static_cast<std::size_t>(dy)].data(), stride4);
    }
    std::vector<Input<std::int32_t>> quad_in;
    for (int dy = 0; dy < 2; ++dy) quad_in.emplace_back(quad[static_cast<std::size_t>(dy)], 0);
    const std::int32_t* quad_sums[2] = {quad_in[0].data(), quad_in[1].data()};
    std::vector<Input<std::uint8_t>> in;
    for (int r = 0; r < 9; r += 4) in.emplace_back(pixel_rows[static_cast<std::size_t>(r)], 0);
    const std::uint8_t* rows[3] = {in[0].data(), in[1].data(), in[2].data()};
    Guarded<std::uint32_t> wa(std::vector<std::uint32_t>(static_cast<std::size_t>(n), 0xA5A5A5A5u), 0xA5A5A5A5u);
    Guarded<std::uint32_t> wb = wa;
    const std::size_t stride = static_cast<std::size_t>(n) + 3;
    Guarded<std::int32_t> sa(std::vector<std::int32_t>(8 * stride, -7), -7);
    Guarded<std::int32_t> sb = sa;
    simd().side8_tests_s32(quad_sums, stride4, rows, n, first_bs, limit.data(), wa.data(), sa.data(), stride);
    scalar().side8_tests_s32(quad_sums, stride4, rows, n, first_bs, limit.data(), wb.data(), sb.data(), stride);
    ASSERT_EQ(diff(wa, wb), "") << what << " n=" << n << " first_backslash=" << first_bs;
    ASSERT_EQ(diff(sa, sb), "") << what << " n=" << n << " first_backslash=" << first_bs;
    for (int m = 0; m < n; ++m) ones |= wb.data()[m], zeros |= ~wb.data()[m];
  };
  const auto limits = [&](int which) {
    std::vector<std::int64_t> l(8);
    for (std::int64_t& v : l) {
      switch (which) {
        case 0: v = static_cast<std::int64_t>(rng() % 200000000u); break;  // mixed on random pixels
        case 1: v = static_cast<std::int64_t>(rng() % 2000000u); break;    // mixed on smooth pixels
        case 2: v = 0; break;                                              // any residual fails
        default: v = INT64_MAX; break;                                     // never
      }
    }
    return l;
  };
  if (!drive_square_kernel(8, 20, rng, run, limits,
                           std::vector<std::int64_t>{200000, 200000, 200000, 200000, 600000, 600000, 600000, 600000}))
    return;
  EXPECT_EQ(ones & 0x3Fu, 0x3Fu) << "some wants bit was never set";
  EXPECT_EQ(zeros & 0x3Fu, 0x3Fu) << "some wants bit was never clear";
}

// Grid rows of the midpoint interpolation: even x of the even rows known
// (the levels above side 2 resolved them), the rest unknown at a rate that
// depends on the case, values as large as Q4 disparities at frac_bits give.
// Every kind of average (horizontal, vertical, both diagonals) must occur.
TEST_P(SimdKernels, MidpointsRowQ4) {
  int kinds[4] = {};  // unknowns resolved: horizontal, vertical, '\\', '/'
  for_each_case(31, [&](int n, int offset, int c, std::mt19937& rng) {
    const int frac_bits = 1 + (offset + 3 * c) % 11;
    const std::int32_t big = std::int32_t{1} << (15 + frac_bits);
    std::uniform_int_distribution<std::int32_t> value(-big, big);
    const int unknown_per_4 = c;  // 0 .. 3 of 4 points that may be unknown are
    const auto grid_row = [&](bool even) {
      std::vector<std::int32_t> r(static_cast<std::size_t>(n) + 2);  // x = -1 .. n
      for (int x = -1; x <= n; ++x) {
        const bool may_be_unknown = !even || (x & 1) != 0;
        const bool unknown = may_be_unknown && static_cast<int>(rng() % 4) < unknown_per_4;
        r[static_cast<std::size_t>(x + 1)] = unknown ? kMidpointUnknown : value(rng);
      }
      return r;
    };
    for (int odd = 0; odd < 2; ++odd) {
      const Input<std::int32_t> above(grid_row(true), offset), row(grid_row(odd == 0), offset),
          below(grid_row(true), offset);
      const int first_bs = (offset >> 1) & 1;
      const std::int32_t* a = odd ? above.data() + 1 : nullptr;
      const std::int32_t* b = odd ? below.data() + 1 : nullptr;
      Guarded<std::int16_t> out_simd(std::vector<std::int16_t>(static_cast<std::size_t>(n), 0x5A5A), 0x5A5A);
      Guarded<std::int16_t> out_scalar = out_simd;
      simd().midpoints_row_q4(a, row.data() + 1, b, n, first_bs, frac_bits, out_simd.data());
      scalar().midpoints_row_q4(a, row.data() + 1, b, n, first_bs, frac_bits, out_scalar.data());
      ASSERT_EQ(diff(out_simd, out_scalar), "")
          << "n=" << n << " offset=" << offset << " odd row=" << odd << " first_backslash=" << first_bs
          << " frac_bits=" << frac_bits;
      for (int x = 0; x < n; ++x) {
        if (row.data()[x + 1] != kMidpointUnknown) continue;
        const bool backslash = ((x >> 1) & 1) == (first_bs ? 0 : 1);
        ++kinds[!odd ? 0 : (x & 1) == 0 ? 1 : backslash ? 2 : 3];
      }
    }
  });
  for (int k = 0; k < 4; ++k) EXPECT_GT(kinds[k], 1000) << "average kind " << k;
}

// The same rows with their confidences (bytes, index for index, few
// distinct values so that ties occur): disparity, confidence and state equal
// the scalar twin's, the disparity midpoints_row_q4's.
TEST_P(SimdKernels, MidpointsRowConfQ4) {
  int resolved = 0;
  for_each_case(31, [&](int n, int offset, int c, std::mt19937& rng) {
    const int frac_bits = 1 + (offset + 3 * c) % 11;
    const std::int32_t big = std::int32_t{1} << (15 + frac_bits);
    std::uniform_int_distribution<std::int32_t> value(-big, big);
    const int unknown_per_4 = c;
    const std::size_t len = static_cast<std::size_t>(n) + 2;  // x = -1 .. n
    const auto grid_row = [&](bool even) {
      std::vector<std::int32_t> r(len);
      for (int x = -1; x <= n; ++x) {
        const bool may_be_unknown = !even || (x & 1) != 0;
        const bool unknown = may_be_unknown && static_cast<int>(rng() % 4) < unknown_per_4;
        r[static_cast<std::size_t>(x + 1)] = unknown ? kMidpointUnknown : value(rng);
      }
      return r;
    };
    const auto conf_row = [&] {
      std::vector<std::uint8_t> r(len);
      for (std::uint8_t& v : r) {
        const std::uint32_t pick = rng() % 8;
        v = static_cast<std::uint8_t>(pick < 3 ? pick * 127 : rng() % 256);
      }
      return r;
    };
    for (int odd = 0; odd < 2; ++odd) {
      const Input<std::int32_t> above(grid_row(true), offset), row(grid_row(odd == 0), offset),
          below(grid_row(true), offset);
      const Input<std::uint8_t> c_above(conf_row(), offset), c_row(conf_row(), offset), c_below(conf_row(), offset);
      const int first_bs = (offset >> 1) & 1;
      const std::int32_t* a = odd ? above.data() + 1 : nullptr;
      const std::int32_t* b = odd ? below.data() + 1 : nullptr;
      const std::uint8_t* ca = odd ? c_above.data() + 1 : nullptr;
      const std::uint8_t* cb = odd ? c_below.data() + 1 : nullptr;
      Guarded<std::int16_t> disp_simd(std::vector<std::int16_t>(static_cast<std::size_t>(n), 0x5A5A), 0x5A5A);
      Guarded<std::int16_t> disp_scalar = disp_simd;
      Guarded<std::uint8_t> conf_simd(std::vector<std::uint8_t>(static_cast<std::size_t>(n), 0xA5), 0xA5);
      Guarded<std::uint8_t> conf_scalar = conf_simd, state_simd = conf_simd, state_scalar = conf_simd;
      simd().midpoints_row_conf_q4(a, row.data() + 1, b, ca, c_row.data() + 1, cb, n, first_bs, frac_bits,
                                   disp_simd.data(), conf_simd.data(), state_simd.data());
      scalar().midpoints_row_conf_q4(a, row.data() + 1, b, ca, c_row.data() + 1, cb, n, first_bs, frac_bits,
                                     disp_scalar.data(), conf_scalar.data(), state_scalar.data());
      const std::string what = "n=" + std::to_string(n) + " offset=" + std::to_string(offset) +
                               " odd row=" + std::to_string(odd) + " first_backslash=" + std::to_string(first_bs) +
                               " frac_bits=" + std::to_string(frac_bits);
      ASSERT_EQ(diff(disp_simd, disp_scalar), "") << what;
      ASSERT_EQ(diff(conf_simd, conf_scalar), "") << what;
      ASSERT_EQ(diff(state_simd, state_scalar), "") << what;
      Guarded<std::int16_t> plain(std::vector<std::int16_t>(static_cast<std::size_t>(n), 0x5A5A), 0x5A5A);
      scalar().midpoints_row_q4(a, row.data() + 1, b, n, first_bs, frac_bits, plain.data());
      ASSERT_EQ(diff(plain, disp_scalar), "") << what;
      for (int x = 0; x < n; ++x) resolved += row.data()[x + 1] == kMidpointUnknown ? 1 : 0;
    }
  });
  EXPECT_GT(resolved, 4000);
}

INSTANTIATE_TEST_SUITE_P(Sets, SimdKernels, ::testing::ValuesIn(test::simd_kernel_params()),
                         test::KernelParamName());
// A build without SIMD (TRISTEREO_WITH_SIMD=OFF, unknown CPU) has nothing to compare.
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(SimdKernels);

}  // namespace
}  // namespace tristereo
