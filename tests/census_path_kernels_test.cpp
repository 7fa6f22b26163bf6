// The census and path-aggregation kernels: every compiled SIMD set against the
// scalar twin (src/kernels/kernels_scalar.hpp) on random and extreme inputs,
// every D from 1 to 256, plus known answers for the scalar definitions.
#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "src/kernels/dispatch.hpp"
#include "src/kernels/kernel_set.hpp"
#include "src/kernels/kernels_scalar.hpp"
#include "support/kernel_param.hpp"

namespace tristereo {
namespace {

constexpr int kSlack = 64;  // the rows' documented read slack

class CensusPathKernels : public ::testing::TestWithParam<KernelChoice> {
 protected:
  void SetUp() override { TRISTEREO_SKIP_UNLESS_RUNNABLE(GetParam()); }
  const KernelSet& simd() const { return kernel_set_for(GetParam()); }
  const KernelSet& scalar() const { return scalar_kernel_set(); }
};

TEST(CensusScalar, KnownDescriptorAndDistance) {
  // 3x3 window around a centre of 5: neighbours 1 9 5 / 4 . 6 / 0 5 7, so the
  // bits (raster order, centre skipped) below 5 are 0, 3 and 5.
  std::vector<std::uint8_t> r0 = {0, 1, 9, 5, 0}, r1 = {0, 4, 5, 6, 0}, r2 = {0, 0, 5, 7, 0};
  const std::uint8_t* rows[3] = {r0.data() + 2, r1.data() + 2, r2.data() + 2};
  std::uint8_t plane = 0;
  std::uint8_t* planes[1] = {&plane};
  census_row_u8_scalar(rows, 3, 3, 1, planes);
  EXPECT_EQ(plane, (1u << 0) | (1u << 3) | (1u << 5));
  std::vector<std::uint8_t> right = {0x00, 0xFF, 0x29};
  const std::uint8_t* rr[1] = {right.data()};
  std::uint16_t sum[3];
  census_window_u16_scalar(rr, &plane, 1, 3, sum);
  EXPECT_EQ(sum[0], 3);
  EXPECT_EQ(sum[1], 5);
  EXPECT_EQ(sum[2], 0);
}

TEST(CensusScalar, BitsGoToBytePlanesInOrder) {
  // 5x5 window, 24 bits: every neighbour below the centre but the ones at
  // bits 7, 8 and 23 (the last bit of plane 0, the first of plane 1, the last
  // of plane 2).
  std::vector<std::vector<std::uint8_t>> r(5, std::vector<std::uint8_t>(5, 10));
  r[2][2] = 100;  // the centre
  r[1][2] = r[1][3] = r[4][4] = 200;  // bits 7, 8 and 23 (raster order, centre skipped)
  const std::uint8_t* rows[5];
  for (int j = 0; j < 5; ++j) rows[j] = r[static_cast<std::size_t>(j)].data() + 2;
  std::uint8_t p0 = 0, p1 = 0, p2 = 0, p3 = 0xAA;
  std::uint8_t* planes[4] = {&p0, &p1, &p2, &p3};
  census_row_u8_scalar(rows, 5, 5, 1, planes);
  EXPECT_EQ(p0, 0x7F);
  EXPECT_EQ(p1, 0xFE);
  EXPECT_EQ(p2, 0x7F);
  EXPECT_EQ(p3, 0xAA);  // three planes hold 24 bits: the fourth is not written
}

TEST_P(CensusPathKernels, CensusRowEqualsScalar) {
  std::mt19937 rng(11);
  const int windows[][2] = {{3, 3}, {5, 5}, {7, 7}, {9, 7}, {7, 9}, {5, 3}, {9, 3}};
  for (const auto& win : windows)
    for (int width : {1, 2, 7, 15, 16, 17, 31, 32, 33, 48, 63, 64, 65, 100, 257}) {
      const int w = win[0], h = win[1];
      const int rx = w / 2;
      const int planes_n = (w * h - 1 + 7) / 8;
      std::uniform_int_distribution<int> px(0, 255), few(0, 3);
      std::vector<std::vector<std::uint8_t>> rows(static_cast<std::size_t>(h));
      std::vector<const std::uint8_t*> rp;
      const bool ties = width % 2 == 0;  // few distinct values: many equal neighbours
      for (auto& r : rows) {
        r.resize(static_cast<std::size_t>(width + 2 * rx));
        for (auto& v : r) v = static_cast<std::uint8_t>(ties ? few(rng) * 85 : px(rng));
        rp.push_back(r.data() + rx);
      }
      std::vector<std::uint8_t> a(static_cast<std::size_t>(8 * width), 0xA5), b = a;
      std::uint8_t* pa[8];
      std::uint8_t* pb[8];
      for (int p = 0; p < 8; ++p) {
        pa[p] = a.data() + p * width;
        pb[p] = b.data() + p * width;
      }
      simd().census_row_u8(rp.data(), w, h, width, pa);
      scalar().census_row_u8(rp.data(), w, h, width, pb);
      ASSERT_EQ(a, b) << w << "x" << h << " width " << width;
      // Planes beyond the descriptor are not written.
      for (int p = planes_n; p < 8; ++p) EXPECT_EQ(a[static_cast<std::size_t>(p * width)], 0xA5);
    }
}

TEST_P(CensusPathKernels, CensusWindowEqualsScalar) {
  std::mt19937 rng(12);
  std::uniform_int_distribution<int> bits(0, 0xFF);
  for (int n = 1; n <= 256; n += (n < 40 ? 1 : 13)) {
    for (int count : {1, 2, 9, 30, 31, 32, 36, 62, 63, 100, 7688}) {
      std::vector<std::vector<std::uint8_t>> right(static_cast<std::size_t>(count));
      std::vector<const std::uint8_t*> rp;
      std::vector<std::uint8_t> left(static_cast<std::size_t>(count));
      for (int i = 0; i < count; ++i) {
        right[static_cast<std::size_t>(i)].resize(static_cast<std::size_t>(n + kSlack));
        // Every entry differing in all 8 bits for some (n, count): the byte
        // sums at their limit (31 x 8 = 248) and the u16 sum at 7688 x 8.
        const bool extreme = count == 7688 ? n % 2 == 0 : (i + n) % 5 == 0;
        for (auto& v : right[static_cast<std::size_t>(i)]) v = static_cast<std::uint8_t>(extreme ? 0xFF : bits(rng));
        left[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(extreme ? 0 : bits(rng));
        rp.push_back(right[static_cast<std::size_t>(i)].data());
      }
      std::vector<std::uint16_t> a(static_cast<std::size_t>(n) + 8, 0x5A5A), b = a;
      simd().census_window_u16(rp.data(), left.data(), count, n, a.data());
      scalar().census_window_u16(rp.data(), left.data(), count, n, b.data());
      ASSERT_EQ(a, b) << "n=" << n << " count=" << count;  // includes the untouched tail
      if (count == 7688 && n % 2 == 0) {
        ASSERT_EQ(b[0], 7688 * 8);
      }
    }
  }
}

// A whole row of per-pixel costs: the SIMD set against the scalar twin, and
// the scalar twin against census_window_u16 per pixel (its definition), for
// 1..8 planes, widths around the lane counts and D from 1 to 256. The stride
// leaves a gap after each pixel's D values that must stay untouched.
TEST_P(CensusPathKernels, CensusCostsRowEqualsScalarAndWindows) {
  std::mt19937 rng(17);
  std::uniform_int_distribution<int> bits(0, 0xFF);
  for (int n = 1; n <= 256; n += (n < 40 ? 1 : 13)) {
    for (int planes = 1; planes <= 8; ++planes) {
      const int width = 1 + (n * 7 + planes * 5) % 40;
      const std::size_t stride = static_cast<std::size_t>(n) + 3;
      // Reversed runs: pixel x reads run[k - x] for k < n (+ slack), x < width.
      std::vector<std::vector<std::uint8_t>> run(static_cast<std::size_t>(planes)), left(run.size());
      std::vector<const std::uint8_t*> rp, lp;
      for (int p = 0; p < planes; ++p) {
        auto& r = run[static_cast<std::size_t>(p)];
        r.resize(static_cast<std::size_t>(width + n + kSlack));
        for (auto& v : r) v = static_cast<std::uint8_t>((p + n) % 5 == 0 ? 0xFF : bits(rng));
        auto& l = left[static_cast<std::size_t>(p)];
        l.resize(static_cast<std::size_t>(width));
        for (auto& v : l) v = static_cast<std::uint8_t>((p + n) % 5 == 0 ? 0x00 : bits(rng));
        rp.push_back(r.data() + width);  // pixel 0's run; pixel x's starts x before
        lp.push_back(l.data());
      }
      std::vector<std::uint16_t> a(stride * static_cast<std::size_t>(width), 0x5A5A), b = a, c = a;
      simd().census_costs_row_u16(rp.data(), lp.data(), planes, width, n, stride, a.data());
      scalar().census_costs_row_u16(rp.data(), lp.data(), planes, width, n, stride, b.data());
      ASSERT_EQ(a, b) << "n=" << n << " planes=" << planes << " width=" << width;
      for (int x = 0; x < width; ++x) {
        std::vector<const std::uint8_t*> rx;
        std::vector<std::uint8_t> lx;
        for (int p = 0; p < planes; ++p) {
          rx.push_back(rp[static_cast<std::size_t>(p)] - x);
          lx.push_back(lp[static_cast<std::size_t>(p)][x]);
        }
        census_window_u16_scalar(rx.data(), lx.data(), planes, n, c.data() + static_cast<std::size_t>(x) * stride);
      }
      ASSERT_EQ(b, c) << "n=" << n << " planes=" << planes << " width=" << width;
      // The byte costs: the same values, and the bytes past n of each pixel
      // untouched.
      std::vector<std::uint8_t> a8(stride * static_cast<std::size_t>(width), 0xA5), b8 = a8;
      simd().census_costs_row_u8(rp.data(), lp.data(), planes, width, n, stride, a8.data());
      scalar().census_costs_row_u8(rp.data(), lp.data(), planes, width, n, stride, b8.data());
      ASSERT_EQ(a8, b8) << "n=" << n << " planes=" << planes << " width=" << width;
      for (std::size_t i = 0; i < b8.size(); ++i)
        ASSERT_EQ(b8[i], i % stride < static_cast<std::size_t>(n) ? b[i] : 0xA5) << "n=" << n << " at " << i;
    }
  }
}

// The previous path costs of `count` paths at one sample, each row its own
// buffer (as in the matcher's rings): n values in [0, bound + p2[r]] (all 0
// when zeros) between 0xFFFF guards, and their minima.
struct PrevRows {
  std::vector<std::vector<std::uint16_t>> rows;
  const std::uint16_t* prev[4] = {};
  std::uint16_t prev_min[4] = {};
  PrevRows(int count, int n, int bound, const std::uint16_t* p2, bool zeros, std::mt19937& rng) {
    for (int r = 0; r < count; ++r) {
      std::uniform_int_distribution<int> pd(0, bound + p2[r]);
      std::vector<std::uint16_t> row(static_cast<std::size_t>(n + 2 + kSlack), 0xFFFF);
      for (int k = 0; k < n; ++k) row[static_cast<std::size_t>(k + 1)] = static_cast<std::uint16_t>(zeros ? 0 : pd(rng));
      prev_min[r] = *std::min_element(row.begin() + 1, row.begin() + 1 + n);
      rows.push_back(std::move(row));
    }
    for (int r = 0; r < count; ++r) prev[r] = rows[static_cast<std::size_t>(r)].data() + 1;
  }
};

// The outputs of `count` paths (n values and canaries each), their sum and minima.
struct PathOutputs {
  std::vector<std::vector<std::uint16_t>> rows;
  std::vector<std::uint16_t> sum;
  std::uint16_t* out[4] = {};
  std::uint16_t mins[4] = {};
  PathOutputs(int count, int n, const std::vector<std::uint16_t>& sum_before)
      : rows(static_cast<std::size_t>(count), std::vector<std::uint16_t>(static_cast<std::size_t>(n) + 4, 0xBEEF)),
        sum(sum_before) {
    for (int r = 0; r < count; ++r) out[r] = rows[static_cast<std::size_t>(r)].data();
  }
  PathOutputs(const PathOutputs&) = delete;
  PathOutputs& operator=(const PathOutputs&) = delete;
};

// Every count of paths, every n, both accumulate modes.
TEST_P(CensusPathKernels, PathStepsEqualScalar) {
  std::mt19937 rng(13);
  for (int n = 1; n <= 256; ++n) {
    for (int c = 0; c < 6; ++c) {
      for (int count = 1; count <= 4; ++count) {
        const int cmax = c == 5 ? 4080 : 1024;
        std::uniform_int_distribution<int> cd(0, cmax);
        std::vector<std::uint16_t> cost(static_cast<std::size_t>(n + kSlack));
        for (int k = 0; k < n; ++k) cost[static_cast<std::size_t>(k)] = static_cast<std::uint16_t>(c == 4 ? cmax : cd(rng));
        std::uint16_t p1[4], p2[4];
        for (int r = 0; r < count; ++r) {
          p1[r] = static_cast<std::uint16_t>((c * 97 + r * 31) % 600);
          p2[r] = static_cast<std::uint16_t>(p1[r] + (c * 331 + r * 57) % 3000);
        }
        const PrevRows in(count, n, cmax, p2, c == 3, rng);
        for (int accumulate = 0; accumulate < 2; ++accumulate) {
          std::vector<std::uint16_t> sum(static_cast<std::size_t>(n) + 4);
          for (auto& v : sum) v = static_cast<std::uint16_t>(cd(rng));
          PathOutputs a(count, n, sum), b(count, n, sum);
          simd().path_steps_u16(cost.data(), in.prev, in.prev_min, p1, p2, count, n, a.out, a.sum.data(), accumulate, a.mins);
          scalar().path_steps_u16(cost.data(), in.prev, in.prev_min, p1, p2, count, n, b.out, b.sum.data(), accumulate, b.mins);
          const std::string at = "n=" + std::to_string(n) + " case " + std::to_string(c) + " count " +
                                 std::to_string(count) + " accumulate " + std::to_string(accumulate);
          ASSERT_EQ(a.rows, b.rows) << at;
          ASSERT_EQ(a.sum, b.sum) << at;
          for (int r = 0; r < count; ++r) {
            ASSERT_EQ(a.mins[r], b.mins[r]) << at << " path " << r;
            ASSERT_EQ(b.mins[r], *std::min_element(b.out[r], b.out[r] + n)) << at << " path " << r;
          }
        }
      }
    }
  }
}

// The byte-sum variant: every compiled set against the scalar twin, with the
// default box's reciprocals and others (the kernel is its formula for any M).
TEST_P(CensusPathKernels, PathStepsU8EqualScalar) {
  std::mt19937 rng(17);
  const std::uint16_t invs[] = {3641, 5459, 8182, 10918, 16363, 32736, 1, 32767};
  for (int n = 1; n <= 256; ++n) {
    for (int count = 1; count <= 4; ++count) {
      const std::uint16_t inv = invs[static_cast<std::size_t>(n + count) % 8];
      std::uniform_int_distribution<int> sd(0, 255);
      std::vector<std::uint8_t> sums(static_cast<std::size_t>(n + kSlack));
      for (int k = 0; k < n; ++k) sums[static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(n % 7 == 0 ? 255 : sd(rng));
      std::uint16_t p1[4], p2[4];
      for (int r = 0; r < count; ++r) {
        p1[r] = static_cast<std::uint16_t>(40 + 30 * r);
        p2[r] = static_cast<std::uint16_t>(p1[r] + 500);
      }
      const PrevRows in(count, n, 4080, p2, false, rng);
      // The definition: path_steps_u16 on the means (16 s M + 2^14) >> 15.
      std::vector<std::uint16_t> cost(static_cast<std::size_t>(n + kSlack));
      for (int k = 0; k < n; ++k)
        cost[static_cast<std::size_t>(k)] =
            static_cast<std::uint16_t>((std::uint32_t{sums[static_cast<std::size_t>(k)]} * 16u * inv + 0x4000u) >> 15);
      for (int accumulate = 0; accumulate < 2; ++accumulate) {
        std::vector<std::uint16_t> sum(static_cast<std::size_t>(n) + 4);
        for (auto& v : sum) v = static_cast<std::uint16_t>(sd(rng) * 20);
        PathOutputs a(count, n, sum), b(count, n, sum), c(count, n, sum);
        simd().path_steps_u8(sums.data(), inv, in.prev, in.prev_min, p1, p2, count, n, a.out, a.sum.data(), accumulate, a.mins);
        scalar().path_steps_u8(sums.data(), inv, in.prev, in.prev_min, p1, p2, count, n, b.out, b.sum.data(), accumulate, b.mins);
        scalar().path_steps_u16(cost.data(), in.prev, in.prev_min, p1, p2, count, n, c.out, c.sum.data(), accumulate, c.mins);
        const std::string at = "n=" + std::to_string(n) + " count " + std::to_string(count) + " inv " +
                               std::to_string(inv) + " accumulate " + std::to_string(accumulate);
        ASSERT_EQ(a.rows, b.rows) << at;
        ASSERT_EQ(a.sum, b.sum) << at;
        ASSERT_EQ(b.rows, c.rows) << at;
        ASSERT_EQ(b.sum, c.sum) << at;
        for (int r = 0; r < count; ++r) {
          ASSERT_EQ(a.mins[r], b.mins[r]) << at << " path " << r;
          ASSERT_EQ(b.mins[r], c.mins[r]) << at << " path " << r;
        }
      }
    }
  }
}

// The scalar twin is one path at a time: the first path's sum with
// `accumulate`, the others added.
TEST(PathStepsScalar, EqualsOnePathAtATime) {
  const std::vector<std::uint16_t> cost = {1, 2, 3};
  const std::vector<std::uint16_t> prev_a = {0xFFFF, 10, 0, 30, 0xFFFF}, prev_b = {0xFFFF, 4, 9, 1, 0xFFFF};
  const std::uint16_t* prev[2] = {prev_a.data() + 1, prev_b.data() + 1};
  const std::uint16_t prev_min[2] = {0, 1}, p1[2] = {5, 2}, p2[2] = {12, 6};
  std::vector<std::uint16_t> oa(3), ob(3), sum = {100, 100, 100};
  std::uint16_t* out[2] = {oa.data(), ob.data()};
  std::uint16_t mins[2] = {};
  path_steps_u16_scalar(cost.data(), prev, prev_min, p1, p2, 2, 3, out, sum.data(), 0, mins);
  // Path a as in KnownStep below: 6 2 8. Path b: min(prev[k], prev[k +- 1] + 2,
  // 1 + 6) - 1 = 3 2 0, plus the costs -> 4 4 3.
  EXPECT_EQ(oa, (std::vector<std::uint16_t>{6, 2, 8}));
  EXPECT_EQ(ob, (std::vector<std::uint16_t>{4, 4, 3}));
  EXPECT_EQ(sum, (std::vector<std::uint16_t>{10, 6, 11}));
  EXPECT_EQ(mins[0], 2);
  EXPECT_EQ(mins[1], 3);
}

TEST(PathStepScalar, KnownStep) {
  // prev = 10 0 30 (min 0), P1 = 5, P2 = 12: best = min(prev[k], neighbours + 5, 12)
  // = 5, 0, 5 -> out = cost + best = 1+5, 2+0, 3+5.
  std::vector<std::uint16_t> prev = {0xFFFF, 10, 0, 30, 0xFFFF}, cost = {1, 2, 3}, out(3), sum = {100, 100, 100};
  const std::uint16_t m = path_step_u16_scalar(cost.data(), prev.data() + 1, 0, 5, 12, 3, out.data(), sum.data(), 1);
  EXPECT_EQ(out, (std::vector<std::uint16_t>{6, 2, 8}));
  EXPECT_EQ(sum, (std::vector<std::uint16_t>{106, 102, 108}));
  EXPECT_EQ(m, 2);
}

TEST(LrMinScalar, KeepsTheSmallestCostAndOnTiesTheFirstOffered) {
  // Two samples offer to the same right pixels; the first offered keeps ties,
  // and 0xFFFF (above every summed cost) never replaces the start value.
  std::vector<std::uint16_t> best(3, 0xFFFF), k(3, 99);
  const std::vector<std::uint16_t> first = {5, 7, 0xFFFF}, second = {5, 6, 0xFFFF};
  lr_min_u16_scalar(first.data(), 3, best.data(), k.data());
  EXPECT_EQ(best, (std::vector<std::uint16_t>{5, 7, 0xFFFF}));
  EXPECT_EQ(k, (std::vector<std::uint16_t>{0, 1, 99}));
  k = {9, 9, 9};
  lr_min_u16_scalar(second.data(), 3, best.data(), k.data());
  EXPECT_EQ(best, (std::vector<std::uint16_t>{5, 6, 0xFFFF}));
  EXPECT_EQ(k, (std::vector<std::uint16_t>{9, 1, 9}));
}

TEST_P(CensusPathKernels, SumRowsEqualsScalar) {
  std::mt19937 rng(17);
  std::uniform_int_distribution<int> v(0, 65535);  // the sums wrap mod 2^16 alike
  for (int count = 1; count <= 9; ++count)
    for (std::size_t n : {std::size_t{1}, std::size_t{7}, std::size_t{16}, std::size_t{33}, std::size_t{256}, std::size_t{1000}}) {
      std::vector<std::vector<std::uint16_t>> rows(static_cast<std::size_t>(count), std::vector<std::uint16_t>(n));
      std::vector<const std::uint16_t*> rp;
      for (auto& r : rows) {
        for (auto& x : r) x = static_cast<std::uint16_t>(v(rng));
        rp.push_back(r.data());
      }
      std::vector<std::uint16_t> a(n, 1), b(n, 2);
      simd().sum_rows_u16(rp.data(), count, n, a.data());
      scalar().sum_rows_u16(rp.data(), count, n, b.data());
      ASSERT_EQ(a, b) << "count=" << count << " n=" << n;
      std::uint32_t s0 = 0;
      for (const auto& r : rows) s0 += r[0];
      ASSERT_EQ(b[0], static_cast<std::uint16_t>(s0));
    }
}

TEST_P(CensusPathKernels, SumRowsU8EqualsScalar) {
  std::mt19937 rng(18);
  std::uniform_int_distribution<int> v(0, 255);  // the sums wrap mod 2^8 alike
  for (int count = 1; count <= 25; count += (count < 9 ? 1 : 8))
    for (std::size_t n : {std::size_t{1}, std::size_t{7}, std::size_t{16}, std::size_t{31}, std::size_t{32},
                          std::size_t{33}, std::size_t{64}, std::size_t{100}, std::size_t{1000}}) {
      std::vector<std::vector<std::uint8_t>> rows(static_cast<std::size_t>(count), std::vector<std::uint8_t>(n));
      std::vector<const std::uint8_t*> rp;
      for (auto& r : rows) {
        for (auto& x : r) x = static_cast<std::uint8_t>(v(rng));
        rp.push_back(r.data());
      }
      std::vector<std::uint8_t> a(n + 1, 1), b(n + 1, 2);
      simd().sum_rows_u8(rp.data(), count, n, a.data());
      scalar().sum_rows_u8(rp.data(), count, n, b.data());
      ASSERT_EQ(std::vector<std::uint8_t>(a.begin(), a.end() - 1), std::vector<std::uint8_t>(b.begin(), b.end() - 1))
          << "count=" << count << " n=" << n;
      ASSERT_EQ(a[n], 1);
      for (std::size_t j = 0; j < n; ++j) {
        std::uint32_t s0 = 0;
        for (const auto& r : rows) s0 += r[j];
        ASSERT_EQ(b[j], static_cast<std::uint8_t>(s0));
      }
    }
}

TEST(MinOutsideScalar, SkipsTheWinnerAndItsNeighbours) {
  const std::vector<std::uint16_t> v = {4, 1, 2, 3, 8};
  EXPECT_EQ(min_outside_u16_scalar(v.data(), 5, 2), 4);       // 1, 2, 3 skipped
  EXPECT_EQ(min_outside_u16_scalar(v.data(), 5, 0), 2);       // 4, 1 skipped
  EXPECT_EQ(min_outside_u16_scalar(v.data(), 5, 4), 1);
  EXPECT_EQ(min_outside_u16_scalar(v.data(), 3, 1), 0xFFFF);  // nothing outside
}

TEST(WinnerScalar, IsTheThreeKernelsInOne) {
  // Ties: the smallest k wins; the rival skips k - 1 .. k + 1; the right
  // view's winners as lr_min_u16 leaves them.
  const std::vector<std::uint16_t> s = {9, 3, 5, 3, 4, 7};
  std::uint16_t rival = 0;
  std::vector<std::uint16_t> best = {4, 4, 4, 4, 4, 4}, k = {8, 8, 8, 8, 8, 8};
  EXPECT_EQ(winner_u16_scalar(s.data(), 6, &rival, best.data(), k.data()), 1);
  EXPECT_EQ(rival, 3);  // s[3]: |3 - 1| > 1
  EXPECT_EQ(best, (std::vector<std::uint16_t>{4, 3, 4, 3, 4, 4}));
  EXPECT_EQ(k, (std::vector<std::uint16_t>{8, 1, 8, 3, 8, 8}));
  EXPECT_EQ(winner_u16_scalar(s.data(), 3, &rival, nullptr, nullptr), 1);
  EXPECT_EQ(rival, 0xFFFF);  // nothing outside 0 .. 2
  EXPECT_EQ(winner_u16_scalar(s.data(), 1, nullptr, nullptr, nullptr), 0);
}

// Against the scalar twin, and the twin against the definitions it stands
// for: the first argmin, min_outside_u16_scalar, lr_min_u16_scalar.
TEST_P(CensusPathKernels, WinnerEqualsScalar) {
  std::mt19937 rng(18);
  for (int n = 1; n <= 256; ++n)
    for (int trial = 0; trial < 6; ++trial) {
      // Small values: ties for the winner, the rival and the right view.
      std::uniform_int_distribution<int> v(trial < 2 ? 0 : 2, trial < 2 ? 3 : 65534);
      std::vector<std::uint16_t> total(static_cast<std::size_t>(n) + kSlack);
      std::vector<std::uint16_t> best_a(total.size()), k_a(total.size());
      for (auto& x : total) x = static_cast<std::uint16_t>(v(rng));
      for (auto& x : best_a) x = static_cast<std::uint16_t>(v(rng));
      for (auto& x : k_a) x = static_cast<std::uint16_t>(v(rng));
      const int dip = std::uniform_int_distribution<int>(0, n - 1)(rng);
      if (trial == 2) {  // the winner and, just above it, its neighbours: the rival must skip them
        total[static_cast<std::size_t>(dip)] = 0;
        if (dip > 0) total[static_cast<std::size_t>(dip - 1)] = 1;
        if (dip + 1 < n) total[static_cast<std::size_t>(dip + 1)] = 1;
      }
      if (trial == 3) total[static_cast<std::size_t>(n - 1)] = 0;  // the winner in the last lane
      if (trial == 4) total[static_cast<std::size_t>(n - 1)] = best_a[static_cast<std::size_t>(n - 1)] = 0xFFFF;
      if (trial == 5) std::fill(total.begin(), total.begin() + n, std::uint16_t{0xFFFF});  // no lane ever lowered
      std::vector<std::uint16_t> best_b = best_a, k_b = k_a, best_c = best_a, k_c = k_a;
      const bool lr = trial != 1;
      std::uint16_t rival_a = 1, rival_b = 2;
      const int ka = simd().winner_u16(total.data(), n, &rival_a, lr ? best_a.data() : nullptr, k_a.data());
      const int kb = scalar().winner_u16(total.data(), n, &rival_b, lr ? best_b.data() : nullptr, k_b.data());
      ASSERT_EQ(ka, kb) << "n=" << n << " trial=" << trial;
      ASSERT_EQ(rival_a, rival_b) << "n=" << n << " trial=" << trial;
      ASSERT_EQ(best_a, best_b) << "n=" << n << " trial=" << trial;
      ASSERT_EQ(k_a, k_b) << "n=" << n << " trial=" << trial;
      ASSERT_EQ(simd().winner_u16(total.data(), n, nullptr, nullptr, nullptr), kb);
      for (int j = 0; j < n; ++j) {
        ASSERT_LE(total[static_cast<std::size_t>(kb)], total[static_cast<std::size_t>(j)]);
        if (j < kb) {
          ASSERT_LT(total[static_cast<std::size_t>(kb)], total[static_cast<std::size_t>(j)]);
        }
      }
      ASSERT_EQ(rival_b, min_outside_u16_scalar(total.data(), n, kb));
      if (trial == 5) {
        ASSERT_EQ(kb, 0);
      }
      if (trial == 2) {
        ASSERT_EQ(kb, dip);
        ASSERT_GT(rival_b, 1) << "n=" << n << " dip=" << dip;  // 0xFFFF when nothing is outside
      }
      if (lr) {
        lr_min_u16_scalar(total.data(), n, best_c.data(), k_c.data());
      }
      ASSERT_EQ(best_b, best_c) << "n=" << n << (lr ? "" : ": no best_cost, nothing written");
      ASSERT_EQ(k_b, k_c) << "n=" << n;
    }
}

INSTANTIATE_TEST_SUITE_P(Sets, CensusPathKernels, ::testing::ValuesIn(test::simd_kernel_params()),
                         test::KernelParamName());
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(CensusPathKernels);

}  // namespace
}  // namespace tristereo
