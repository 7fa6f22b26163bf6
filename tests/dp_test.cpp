// The per-row DP (docs/model.md section 3): penalty tables, the O(D) dp_step
// against the O(D^2) recurrence (ties included), exact optimality and tie rule
// against enumeration of every assignment, sub-pixel rounding, and exact
// disparities on a synthetic fronto-parallel plane.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "src/cost/match_context.hpp"
#include "src/dp/penalty.hpp"
#include "src/dp/row_matcher.hpp"
#include "src/dp/subpixel.hpp"
#include "src/kernels/dispatch.hpp"
#include "src/kernels/kernel_set.hpp"
#include "support/kernel_param.hpp"
#include "src/reference/ref_match.hpp"
#include "tristereo/status.hpp"

namespace tristereo {
namespace {

TEST(Penalty, HandValuesPerPolicy) {
  // lambda = 160: inv -> 160, 80, 53 (53.3), 40; inv_sq -> 160, 40, 18 (17.8), 10, 4 (4.44 at g = 6).
  EXPECT_EQ(gap_penalty_q4(160, GapPolicy::kInverse, 1), 160u);
  EXPECT_EQ(gap_penalty_q4(160, GapPolicy::kInverse, 2), 80u);
  EXPECT_EQ(gap_penalty_q4(160, GapPolicy::kInverse, 3), 53u);
  EXPECT_EQ(gap_penalty_q4(160, GapPolicy::kInvSquare, 1), 160u);
  EXPECT_EQ(gap_penalty_q4(160, GapPolicy::kInvSquare, 2), 40u);
  EXPECT_EQ(gap_penalty_q4(160, GapPolicy::kInvSquare, 3), 18u);
  EXPECT_EQ(gap_penalty_q4(160, GapPolicy::kInvSquare, 6), 4u);
  EXPECT_EQ(gap_penalty_q4(160, GapPolicy::kConstant, 977), 160u);
  // Halves go up: 10 / 4 = 2.5 -> 3, 2 / 4 = 0.5 -> 1, 7 / 2 = 3.5 -> 4.
  EXPECT_EQ(gap_penalty_q4(10, GapPolicy::kInverse, 4), 3u);
  EXPECT_EQ(gap_penalty_q4(2, GapPolicy::kInvSquare, 2), 1u);
  EXPECT_EQ(gap_penalty_q4(7, GapPolicy::kInverse, 2), 4u);
  EXPECT_EQ(gap_penalty_q4(0, GapPolicy::kConstant, 3), 0u);
  EXPECT_EQ(gap_penalty_q4(32000, GapPolicy::kInvSquare, 4095), 0u);  // 0.0019
}

TEST(Penalty, TableEqualsReferenceForEveryGap) {
  std::mt19937 rng(3);
  for (GapPolicy g : {GapPolicy::kInvSquare, GapPolicy::kInverse, GapPolicy::kConstant}) {
    for (int lambda : {0, 1, 2, 159, 160, 161, 4095, 31999, 32000,
                       std::uniform_int_distribution<int>(0, 32000)(rng)}) {
      std::vector<std::uint32_t> table;
      fill_penalty_table(lambda, g, 4095, table);
      ASSERT_EQ(table.size(), 4096u);
      DpParams dp;
      dp.lambda_q4 = lambda;
      dp.gap = g;
      for (int gap = 1; gap <= 4095; ++gap) {
        ASSERT_EQ(table[static_cast<std::size_t>(gap)],
                  static_cast<std::uint32_t>(reference::gap_penalty(dp, gap)))
            << to_string(g) << " lambda " << lambda << " gap " << gap;
        ASSERT_LE(table[static_cast<std::size_t>(gap)], static_cast<std::uint32_t>(lambda));
      }
    }
  }
}

// ---------------------------------------------------------------- dp_step

TEST(DpStep, ScalarEqualsBruteForceIncludingTies) {
  std::mt19937 rng(21);
  const KernelSet& ks = scalar_kernel_set();
  for (int trial = 0; trial < 3000; ++trial) {
    const int n = trial < 256 ? trial + 1 : std::uniform_int_distribution<int>(1, 256)(rng);
    // Narrow value ranges and penalty 0 produce many ties.
    const int mode = trial % 4;
    const std::uint32_t penalty =
        mode == 0 ? 0u : mode == 1 ? 1u : std::uniform_int_distribution<std::uint32_t>(0, 32000)(rng);
    const std::uint32_t vmax = mode == 3 ? 4080 + 255 * penalty : 3;
    std::uniform_int_distribution<std::uint32_t> val(0, vmax);
    std::uniform_int_distribution<int> cost(0, mode == 3 ? 4080 : 2);
    std::vector<std::uint16_t> c(static_cast<std::size_t>(n));
    std::vector<std::uint32_t> prev(static_cast<std::size_t>(n));
    std::vector<std::int64_t> c64(c.size()), prev64(prev.size()), want;
    for (int k = 0; k < n; ++k) {
      c[static_cast<std::size_t>(k)] = static_cast<std::uint16_t>(cost(rng));
      prev[static_cast<std::size_t>(k)] = trial % 7 == 0 ? 5u : val(rng);  // all-equal rows too
      c64[static_cast<std::size_t>(k)] = c[static_cast<std::size_t>(k)];
      prev64[static_cast<std::size_t>(k)] = prev[static_cast<std::size_t>(k)];
    }
    std::vector<std::uint32_t> out(static_cast<std::size_t>(n) + 1, 0xDEADBEEF);
    std::vector<std::uint8_t> ptr(static_cast<std::size_t>(n) + 1, 0xAB);
    ks.dp_step(c.data(), prev.data(), penalty, n, out.data(), ptr.data());
    std::vector<int> want_ptr;
    reference::dp_step_brute_force(c64, prev64, penalty, want, want_ptr);
    for (int k = 0; k < n; ++k) {
      ASSERT_EQ(out[static_cast<std::size_t>(k)], static_cast<std::uint64_t>(want[static_cast<std::size_t>(k)]))
          << "trial " << trial << " k " << k;
      ASSERT_EQ(ptr[static_cast<std::size_t>(k)], want_ptr[static_cast<std::size_t>(k)])
          << "trial " << trial << " k " << k;
    }
    EXPECT_EQ(out[static_cast<std::size_t>(n)], 0xDEADBEEFu);
    EXPECT_EQ(ptr[static_cast<std::size_t>(n)], 0xAB);
  }
}

TEST(DpStep, TiesGoToTheSmallestIndex) {
  // prev = [4, 0, 0, 4], P = 2: g(3) = min(4+6, 0+4, 0+2, 4) = 2 at j = 2;
  // g(0) = min(4, 2, 4, 10) = 2 at j = 1; with P = 0 every g = 0 at j = 1.
  const std::uint16_t cost[4] = {0, 0, 0, 0};
  const std::uint32_t prev[4] = {4, 0, 0, 4};
  std::uint32_t out[4];
  std::uint8_t ptr[4];
  scalar_kernel_set().dp_step(cost, prev, 2, 4, out, ptr);
  EXPECT_EQ(ptr[0], 1);
  EXPECT_EQ(ptr[1], 1);
  EXPECT_EQ(ptr[2], 2);
  EXPECT_EQ(ptr[3], 2);
  EXPECT_EQ(out[0], 2u);  // g - min g = 2 - 0
  scalar_kernel_set().dp_step(cost, prev, 0, 4, out, ptr);
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(ptr[k], 1);
    EXPECT_EQ(out[k], 0u);
  }
}

// ---------------------------------------------------------------- whole-row DP

TEST(RowDp, OptimalAndTieBrokenAgainstEnumeration) {
  std::mt19937 rng(99);
  const KernelSet& ks = scalar_kernel_set();
  for (int trial = 0; trial < 4000; ++trial) {
    const int n = std::uniform_int_distribution<int>(1, 5)(rng);
    const int d = std::uniform_int_distribution<int>(1, 6)(rng);
    const bool ties = trial % 2 == 0;
    std::uniform_int_distribution<int> cost(0, ties ? 3 : 4080);
    std::uniform_int_distribution<int> pen(0, ties ? 2 : 3000);
    const std::size_t stride = 8;
    std::vector<std::uint16_t> costs(stride * static_cast<std::size_t>(n));
    std::vector<std::vector<std::int64_t>> cost64(static_cast<std::size_t>(n), std::vector<std::int64_t>(static_cast<std::size_t>(d)));
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < d; ++k)
        cost64[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)] =
            costs[static_cast<std::size_t>(i) * stride + static_cast<std::size_t>(k)] = static_cast<std::uint16_t>(cost(rng));
    // Gap i between samples i-1 and i, so penalty_by_gap[i] is sample i's penalty.
    std::vector<std::int32_t> xs(static_cast<std::size_t>(n));
    std::vector<std::uint32_t> by_gap(8, 0);
    std::vector<std::int64_t> pen64(static_cast<std::size_t>(n), 0);
    for (int i = 1; i < n; ++i) {
      xs[static_cast<std::size_t>(i)] = xs[static_cast<std::size_t>(i) - 1] + i;
      by_gap[static_cast<std::size_t>(i)] = static_cast<std::uint32_t>(pen(rng));
      pen64[static_cast<std::size_t>(i)] = by_gap[static_cast<std::size_t>(i)];
    }

    // Enumerate all d^n assignments; keep the minimum energy and, among the
    // minimisers, the one that is smallest comparing k_n first, then k_{n-1}...
    std::int64_t best_e = std::numeric_limits<std::int64_t>::max();
    std::vector<int> best, ks_vec(static_cast<std::size_t>(n), 0);
    for (;;) {
      std::int64_t e = 0;
      for (int i = 0; i < n; ++i) {
        e += cost64[static_cast<std::size_t>(i)][static_cast<std::size_t>(ks_vec[static_cast<std::size_t>(i)])];
        if (i > 0) e += pen64[static_cast<std::size_t>(i)] * std::abs(ks_vec[static_cast<std::size_t>(i)] - ks_vec[static_cast<std::size_t>(i) - 1]);
      }
      auto rev_less = [&](const std::vector<int>& a, const std::vector<int>& b) {
        for (int i = n - 1; i >= 0; --i)
          if (a[static_cast<std::size_t>(i)] != b[static_cast<std::size_t>(i)]) return a[static_cast<std::size_t>(i)] < b[static_cast<std::size_t>(i)];
        return false;
      };
      if (e < best_e || (e == best_e && rev_less(ks_vec, best))) {
        best_e = e;
        best = ks_vec;
      }
      int i = 0;
      while (i < n && ++ks_vec[static_cast<std::size_t>(i)] == d) ks_vec[static_cast<std::size_t>(i++)] = 0;
      if (i == n) break;
    }

    std::vector<std::uint32_t> fa(stride), fb(stride);
    std::vector<std::uint8_t> ptr(stride * static_cast<std::size_t>(n));
    std::vector<std::int32_t> got(static_cast<std::size_t>(n));
    solve_row_dp(ks, costs.data(), stride, xs.data(), n, d, by_gap.data(), fa.data(), fb.data(),
                 ptr.data(), got.data());
    const std::vector<int> ref = reference::dp_solve(cost64, pen64);
    for (int i = 0; i < n; ++i) {
      ASSERT_EQ(got[static_cast<std::size_t>(i)], best[static_cast<std::size_t>(i)]) << "trial " << trial << " sample " << i;
      ASSERT_EQ(ref[static_cast<std::size_t>(i)], best[static_cast<std::size_t>(i)]) << "trial " << trial << " sample " << i;
    }
  }
}

// ---------------------------------------------------------------- u16 DP path

TEST(DpStepU16, ScalarEqualsBruteForce) {
  std::mt19937 rng(22);
  const KernelSet& ks = scalar_kernel_set();
  for (int trial = 0; trial < 3000; ++trial) {
    const int n = trial < 256 ? trial + 1 : std::uniform_int_distribution<int>(1, 256)(rng);
    const int mode = trial % 4;
    const std::uint32_t penalty = mode == 0 ? 0u : mode == 1 ? kMaxDpPenaltyU16
                                  : std::uniform_int_distribution<std::uint32_t>(0, kMaxDpPenaltyU16)(rng);
    const std::uint32_t vmax = mode == 3 ? 3 : 4080 + 255 * penalty;
    std::uniform_int_distribution<std::uint32_t> val(0, vmax);
    std::vector<std::uint16_t> c(static_cast<std::size_t>(n)), prev(c.size());
    std::vector<std::int64_t> c64(c.size()), prev64(c.size()), want;
    std::vector<int> want_ptr;
    for (std::size_t k = 0; k < c.size(); ++k) {
      c[k] = static_cast<std::uint16_t>(rng() % 4081);
      prev[k] = static_cast<std::uint16_t>(val(rng));
      c64[k] = c[k];
      prev64[k] = prev[k];
    }
    std::vector<std::uint16_t> out(c.size() + 1, 0xBEEF);
    ks.dp_step_u16(c.data(), prev.data(), penalty, n, out.data());
    reference::dp_step_brute_force(c64, prev64, penalty, want, want_ptr);
    for (int k = 0; k < n; ++k) {
      ASSERT_EQ(out[static_cast<std::size_t>(k)], want[static_cast<std::size_t>(k)]) << "trial " << trial << " k " << k;
      ASSERT_EQ(ks.dp_pointer_u16(prev.data(), penalty, n, k), want_ptr[static_cast<std::size_t>(k)])
          << "trial " << trial << " k " << k;
    }
    EXPECT_EQ(out[static_cast<std::size_t>(n)], 0xBEEF);
  }
}

class RowDpU16 : public ::testing::TestWithParam<KernelChoice> {};

// The u16 row solver (F rows kept, pointers recomputed on the path) picks the
// same disparities as the u32 one with stored pointers, for every kernel set,
// on random rows with many ties and at the largest lambda the u16 path takes.
TEST_P(RowDpU16, EqualsTheU32Path) {
  TRISTEREO_SKIP_UNLESS_RUNNABLE(GetParam());
  const KernelSet& ks = kernel_set_for(GetParam());
  std::mt19937 rng(123);
  for (int trial = 0; trial < 300; ++trial) {
    const int d = trial < 40 ? 1 + trial : std::uniform_int_distribution<int>(1, 256)(rng);
    const int n = std::uniform_int_distribution<int>(1, 120)(rng);
    const int mode = trial % 3;
    const std::uint32_t lambda = mode == 0 ? kMaxDpPenaltyU16 : mode == 1 ? 1 : 40;
    const int cmax = mode == 1 ? 3 : 4080;
    const std::size_t stride = (static_cast<std::size_t>(d) + 64 + 63) / 64 * 64;
    std::vector<std::uint16_t> costs(stride * static_cast<std::size_t>(n));
    for (auto& v : costs) v = static_cast<std::uint16_t>(rng() % (cmax + 1));
    std::vector<std::int32_t> xs(static_cast<std::size_t>(n));
    for (int i = 1; i < n; ++i) xs[static_cast<std::size_t>(i)] = xs[static_cast<std::size_t>(i) - 1] + 1 + static_cast<std::int32_t>(rng() % 4);
    std::vector<std::uint32_t> by_gap;
    fill_penalty_table(static_cast<int>(lambda), trial % 2 ? GapPolicy::kInverse : GapPolicy::kConstant,
                       xs.back() + 1, by_gap);
    std::vector<std::uint32_t> fa(stride), fb(stride);
    std::vector<std::uint8_t> ptr(stride * static_cast<std::size_t>(n));
    std::vector<std::uint16_t> f_rows(stride * static_cast<std::size_t>(n));
    std::vector<std::int32_t> want(static_cast<std::size_t>(n)), got(static_cast<std::size_t>(n));
    solve_row_dp(scalar_kernel_set(), costs.data(), stride, xs.data(), n, d, by_gap.data(), fa.data(),
                 fb.data(), ptr.data(), want.data());
    solve_row_dp_u16(ks, costs.data(), stride, xs.data(), n, d, by_gap.data(), f_rows.data(), got.data());
    ASSERT_EQ(got, want) << "trial " << trial << " n " << n << " D " << d << " lambda " << lambda;
  }
}

INSTANTIATE_TEST_SUITE_P(Sets, RowDpU16, ::testing::ValuesIn(test::all_kernel_params()),
                         test::KernelParamName());

// ---------------------------------------------------------------- sub-pixel

TEST(Subpixel, HandValues) {
  EXPECT_EQ(subpixel_offset_q4(10, 0, 10), 0);   // symmetric
  EXPECT_EQ(subpixel_offset_q4(20, 0, 10), 3);   // 10 / 60 px = 2.67 -> 3
  EXPECT_EQ(subpixel_offset_q4(10, 0, 20), -3);
  EXPECT_EQ(subpixel_offset_q4(19, 0, 13), 2);   // exactly 1.5 -> 2 (half up)
  EXPECT_EQ(subpixel_offset_q4(13, 0, 19), -1);  // exactly -1.5 -> -1
  EXPECT_EQ(subpixel_offset_q4(1, 0, 0), 8);     // 8.5 -> clamp 8
  EXPECT_EQ(subpixel_offset_q4(0, 0, 100), -8);  // clamp
  EXPECT_EQ(subpixel_offset_q4(0, 5, 0), 0);     // den < 0: no minimum
  EXPECT_EQ(subpixel_offset_q4(3, 5, 7), 0);     // den = 0: a line
}

TEST(Subpixel, IntegerRuleEqualsReferenceAndExactRational) {
  auto exact = [](int cm, int c0, int cp) {
    const int den = cm + cp - 2 * c0;
    if (den <= 0) return 0;
    // Largest m with m <= 16 (cm - cp) / (2 den) + 1/2, i.e. 2 den m <= 16 (cm - cp) + den.
    // Only -9..9 matter after the clamp; below -9 clamps to -8 like -9 does.
    const long num = 16L * (cm - cp) + den;
    long m = -9;
    while (m < 9 && 2L * den * (m + 1) <= num) ++m;
    return static_cast<int>(std::clamp<long>(m, -8, 8));
  };
  for (int cm = 0; cm <= 64; ++cm)
    for (int c0 = 0; c0 <= 64; c0 += 3)
      for (int cp = 0; cp <= 64; ++cp) {
        const int want = exact(cm, c0, cp);
        ASSERT_EQ(subpixel_offset_q4(cm, c0, cp), want) << cm << " " << c0 << " " << cp;
        ASSERT_EQ(reference::subpixel_offset_q4(cm, c0, cp), want) << cm << " " << c0 << " " << cp;
      }
  std::mt19937 rng(4);
  std::uniform_int_distribution<int> v(0, 4080);
  for (int t = 0; t < 20000; ++t) {
    const int cm = v(rng), c0 = v(rng) / (1 + t % 8), cp = v(rng);
    ASSERT_EQ(subpixel_offset_q4(cm, c0, cp), reference::subpixel_offset_q4(cm, c0, cp));
  }
}

TEST(Subpixel, EquiangularHandValues) {
  // m = max(cm, cp) - c0; off = clamp(floor((16 (cm - cp) + m) / (2 m)), -8, 8).
  EXPECT_EQ(equiangular_offset_q4(10, 0, 10), 0);    // symmetric
  EXPECT_EQ(equiangular_offset_q4(30, 10, 20), 4);   // m 20: 160 / 40 = 4 (the parabola: 3)
  EXPECT_EQ(subpixel_offset_q4(30, 10, 20), 3);
  EXPECT_EQ(equiangular_offset_q4(20, 10, 30), -4);
  EXPECT_EQ(equiangular_offset_q4(20, 0, 10), 4);    // m 20: 160 / 40 = 4 exactly
  EXPECT_EQ(equiangular_offset_q4(16, 0, 13), 2);    // m 16: 48 / 32 = 1.5 -> 2 (half up)
  EXPECT_EQ(equiangular_offset_q4(13, 0, 16), -1);   // -1.5 -> -1
  EXPECT_EQ(equiangular_offset_q4(33, 1, 30), 1);    // m 32: 48 / 64 = 0.75 -> 1
  EXPECT_EQ(equiangular_offset_q4(30, 1, 33), -1);   // -0.75 -> -1
  EXPECT_EQ(equiangular_offset_q4(12, 0, 1), 7);     // m 12: 176 / 24 = 7.33 -> 7
  EXPECT_EQ(equiangular_offset_q4(1, 0, 0), 8);      // m 1: 16 / 2 = 8
  EXPECT_EQ(equiangular_offset_q4(10, 5, 0), 8);     // c0 above cp: 160 / 10 = 16 -> clamp 8
  EXPECT_EQ(equiangular_offset_q4(0, 5, 10), -8);    // clamp
  EXPECT_EQ(equiangular_offset_q4(0, 5, 0), 0);      // m < 0: c0 above both
  EXPECT_EQ(equiangular_offset_q4(5, 5, 5), 0);      // m = 0: flat
  EXPECT_EQ(equiangular_offset_q4(3, 7, 7), 0);      // m = 0
  // The largest summed path costs (section 3b): 16 * 65534 fits int32.
  EXPECT_EQ(equiangular_offset_q4(65534, 0, 0), 8);
  EXPECT_EQ(equiangular_offset_q4(65534, 0, 65533), 0);  // 16 / (2 * 65534) -> 0
  EXPECT_EQ(equiangular_offset_q4(65534, 65533, 65534), 0);
  // The dispatch by the model's option.
  EXPECT_EQ(subpixel_offset_q4(SubpixelFit::kEquiangular, 30, 10, 20), 4);
  EXPECT_EQ(subpixel_offset_q4(SubpixelFit::kParabola, 30, 10, 20), 3);
}

// A V-shaped cost (linear on both sides of a vertex at t px) gives its vertex
// back to the nearest 1/16 px with the equiangular fit; the parabola pulls it
// towards the integer disparity (pixel locking).
TEST(Subpixel, EquiangularRecoversTheVertexOfAV) {
  for (int t16 = -8; t16 <= 8; ++t16) {
    const int slope = 64;  // C(k + j) = slope |16 j - t16|: a V with its vertex at t16 / 16 px
    auto c = [&](int j) { return slope * std::abs(16 * j - t16); };
    EXPECT_EQ(equiangular_offset_q4(c(-1), c(0), c(1)), t16) << t16;
    const int para = subpixel_offset_q4(c(-1), c(0), c(1));
    EXPECT_LE(std::abs(para), std::abs(t16)) << t16;
    if (std::abs(t16) >= 2 && std::abs(t16) <= 6) {
      EXPECT_LT(std::abs(para), std::abs(t16)) << t16;
    }
  }
}

TEST(Subpixel, EquiangularIntegerRuleEqualsReferenceAndExactRational) {
  auto exact = [](int cm, int c0, int cp) {
    const int m = std::max(cm, cp) - c0;
    if (m <= 0) return 0;
    // Largest q with 2 m q <= 16 (cm - cp) + m; only -9..9 matter after the clamp.
    const long num = 16L * (cm - cp) + m;
    long q = -9;
    while (q < 9 && 2L * m * (q + 1) <= num) ++q;
    return static_cast<int>(std::clamp<long>(q, -8, 8));
  };
  for (int cm = 0; cm <= 64; ++cm)
    for (int c0 = 0; c0 <= 64; c0 += 3)
      for (int cp = 0; cp <= 64; ++cp) {
        const int want = exact(cm, c0, cp);
        ASSERT_EQ(equiangular_offset_q4(cm, c0, cp), want) << cm << " " << c0 << " " << cp;
        ASSERT_EQ(reference::equiangular_offset_q4(cm, c0, cp), want) << cm << " " << c0 << " " << cp;
      }
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> v(0, 65534);
  for (int t = 0; t < 20000; ++t) {
    const int cm = v(rng), c0 = v(rng) / (1 + t % 8), cp = v(rng);
    const int want = exact(cm, c0, cp);
    ASSERT_EQ(equiangular_offset_q4(cm, c0, cp), want) << cm << " " << c0 << " " << cp;
    ASSERT_EQ(reference::equiangular_offset_q4(cm, c0, cp), want) << cm << " " << c0 << " " << cp;
    ASSERT_EQ(subpixel_offset_q4(cm, c0, cp), reference::subpixel_offset_q4(cm, c0, cp));
  }
}

// ---------------------------------------------------------------- synthetic plane

// Left: random texture; right(x) = left(x + d) (so left x matches right x - d).
TEST(RowMatcher, FrontoParallelPlaneGivesTheExactDisparity) {
  std::mt19937 rng(123);
  std::uniform_int_distribution<int> byte(0, 255);
  const int w = 96, h = 20;
  for (int d_true : {-3, 0, 5, 11}) {
    ImageU8 left(w, h), right(w, h);
    for (auto& p : left.pixels) p = static_cast<std::uint8_t>(byte(rng));
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        right.at(x, y) = (x + d_true >= 0 && x + d_true < w) ? left.at(x + d_true, y)
                                                              : static_cast<std::uint8_t>(byte(rng));
    for (Weights wts : {Weights::kBox, Weights::kAdaptive}) {
      for (int step : {1, 3, 7}) {
        StereoParams p = paper_params();
        p.d_min = -4;
        p.num_disp = 20;
        p.cost.weights = wts;
        p.cost.window_w = wts == Weights::kBox ? 5 : 9;
        p.cost.window_h = wts == Weights::kBox ? 5 : 9;
        // Off: the parabola through a non-parabolic cost curve would move the
        // value away from the integer even though the match is exact.
        p.dp.subpixel = false;
        MatchContext ctx(w, h, p, scalar_kernel_set());
        ctx.begin_frame(std::as_const(left).view(), std::as_const(right).view());
        ctx.prepare_right_rows(0, h);
        RowMatcher matcher(w, p);
        std::vector<std::int32_t> xs;
        for (int x = 0; x < w; x += step) xs.push_back(x);
        std::vector<std::int16_t> disp(xs.size());
        const int r = p.cost.window_w / 2;
        for (int y = 0; y < h; ++y) {
          matcher.match_row(ctx, y, xs.data(), static_cast<int>(xs.size()), disp.data());
          for (std::size_t i = 0; i < xs.size(); ++i) {
            // Interior: the whole window matches without the border rule, for
            // the true d and for every other d searched.
            if (xs[i] - r - (p.d_min + p.num_disp - 1) < 0 || xs[i] + r - p.d_min >= w) continue;
            ASSERT_EQ(disp[i], 16 * d_true) << "d " << d_true << " y " << y << " x " << xs[i]
                                            << " step " << step << " " << to_string(wts);
          }
        }
      }
    }
  }
}

TEST(RowMatcher, RejectsBadSamplesWithoutWriting) {
  StereoParams p = paper_params();
  p.num_disp = 8;
  const ImageU8 img(20, 6, 1, 7);
  MatchContext ctx(32, 8, p, scalar_kernel_set());
  RowMatcher m(32, p);
  std::int16_t out[4] = {1, 2, 3, 4};
  const std::int32_t xs_ok[3] = {0, 5, 19};
  EXPECT_THROW(m.match_row(ctx, 0, xs_ok, 3, out), Error);  // no frame yet
  ctx.begin_frame(img.view(), img.view());
  ctx.prepare_right_rows(0, 6);
  const std::int32_t xs_dup[3] = {0, 5, 5}, xs_far[3] = {0, 5, 20}, xs_neg[3] = {-1, 5, 6};
  EXPECT_THROW(m.match_row(ctx, 0, xs_dup, 3, out), Error);
  EXPECT_THROW(m.match_row(ctx, 0, xs_far, 3, out), Error);
  EXPECT_THROW(m.match_row(ctx, 0, xs_neg, 3, out), Error);
  EXPECT_THROW(m.match_row(ctx, 6, xs_ok, 3, out), Error);
  EXPECT_THROW(m.match_row(ctx, 0, xs_ok, 21, out), Error);
  EXPECT_EQ(out[0], 1);
  EXPECT_EQ(out[3], 4);
  RowMatcher other(32, [&] { StereoParams q = p; q.num_disp = 9; return q; }());
  EXPECT_THROW(other.match_row(ctx, 0, xs_ok, 3, out), Error);
  RowTimes times;
  m.match_row(ctx, 0, xs_ok, 3, out, &times);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(out[i], 0);  // identical images: d = 0
  EXPECT_EQ(out[3], 4);
  EXPECT_THROW(RowMatcher(1, p), Error);
  StereoParams bad = p;
  bad.cost.window_h = 2;
  EXPECT_THROW(RowMatcher(32, bad), Error);
}

}  // namespace
}  // namespace tristereo
