// Cost + aggregation at the samples (docs/model.md section 2): the integer exp
// tables, the scalar cost kernels against naive loops, the reversed right
// rows, aggregate_sample against the reference and hand-computed values, and
// parameter/frame validation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <vector>

#include "src/cost/match_context.hpp"
#include "src/kernels/dispatch.hpp"
#include "src/kernels/kernel_set.hpp"
#include "src/kernels/kernels_scalar.hpp"
#include "src/model/exp_table.hpp"
#include "src/reference/ref_match.hpp"
#include "tristereo/kernels.hpp"
#include "tristereo/status.hpp"

namespace tristereo {
namespace {

ImageU8 random_image(int w, int h, std::mt19937& rng, int lo = 0, int hi = 255) {
  ImageU8 img(w, h, 1);
  std::uniform_int_distribution<int> v(lo, hi);
  for (auto& p : img.pixels) p = static_cast<std::uint8_t>(v(rng));
  return img;
}

TEST(ExpTable, WithinOneOfLibmEverywhere) {
  std::vector<std::uint8_t> t(451);
  for (int gamma = 1; gamma <= 1000; ++gamma) {
    exp_decay_table_u8(gamma, 451, t.data());
    for (int i = 0; i < 451; ++i) {
      const long exact = std::lround(255.0 * std::exp(-static_cast<double>(i) / gamma));
      ASSERT_LE(std::labs(exact - t[static_cast<std::size_t>(i)]), 1) << "gamma " << gamma << " t " << i;
    }
  }
  for (int gamma : {2000, 9999, 65536, 100000}) {
    exp_decay_table_u8(gamma, 451, t.data());
    for (int i = 0; i < 451; ++i) {
      const long exact = std::lround(255.0 * std::exp(-static_cast<double>(i) / gamma));
      ASSERT_LE(std::labs(exact - t[static_cast<std::size_t>(i)]), 1) << "gamma " << gamma << " t " << i;
    }
  }
}

TEST(ExpTable, GoldenValues) {
  std::uint8_t t[64];
  exp_decay_table_u8(10, 64, t);
  const std::uint8_t golden10[16] = {255, 231, 209, 189, 171, 155, 140, 127,
                                     115, 104, 94,  85,  77,  69,  63,  57};
  for (int i = 0; i < 16; ++i) EXPECT_EQ(t[i], golden10[i]) << i;
  EXPECT_EQ(t[62], 1);
  EXPECT_EQ(t[63], 0);
  exp_decay_table_u8(50, 64, t);
  EXPECT_EQ(t[1], 250);
  EXPECT_EQ(t[50], 94);
  EXPECT_EQ(t[63], 72);
  // Cases where the exact value is within 1e-5 of a half: the integer table is
  // pinned (libm-independent), here 110 although 255 e^{-526/629} = 110.500001.
  std::vector<std::uint8_t> big(527);
  exp_decay_table_u8(629, 527, big.data());
  EXPECT_EQ(big[526], 110);
  exp_decay_table_u8(1, 8, t);
  const std::uint8_t golden1[8] = {255, 94, 35, 13, 5, 2, 1, 0};
  for (int i = 0; i < 8; ++i) EXPECT_EQ(t[i], golden1[i]) << i;
}

// ---------------------------------------------------------------- scalar kernels

TEST(CostKernelsScalar, MatchNaiveLoops) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> byte(0, 255);
  const KernelSet& ks = scalar_kernel_set();
  for (int n : {0, 1, 2, 15, 16, 17, 31, 32, 33, 64, 255, 256}) {
    for (int trial = 0; trial < 20; ++trial) {
      std::vector<std::uint8_t> rrev(static_cast<std::size_t>(n) + 1);
      for (auto& v : rrev) v = static_cast<std::uint8_t>(byte(rng));
      const auto left = static_cast<std::uint8_t>(byte(rng));
      const auto trunc = static_cast<std::uint8_t>(std::max(1, byte(rng)));
      const auto weight = static_cast<std::uint16_t>(byte(rng));
      std::vector<std::uint16_t> acc16(static_cast<std::size_t>(n) + 1), want16;
      std::vector<std::uint32_t> acc32(static_cast<std::size_t>(n) + 1), want32;
      for (auto& v : acc16) v = static_cast<std::uint16_t>(byte(rng) * 200);
      for (auto& v : acc32) v = static_cast<std::uint32_t>(byte(rng) * 100000);
      want16 = acc16;
      want32 = acc32;
      for (int k = 0; k < n; ++k) {
        const int c = std::min(std::abs(left - rrev[static_cast<std::size_t>(k)]), int{trunc});
        want16[static_cast<std::size_t>(k)] = static_cast<std::uint16_t>(want16[static_cast<std::size_t>(k)] + c);
        want32[static_cast<std::size_t>(k)] += weight * static_cast<std::uint32_t>(c);
      }
      ks.accumulate_abs_diff_u16(rrev.data(), left, trunc, n, acc16.data());
      ks.accumulate_abs_diff_weighted_u32(rrev.data(), left, weight, trunc, n, acc32.data());
      ASSERT_EQ(acc16, want16) << "n " << n;  // the guard element past n is untouched too
      ASSERT_EQ(acc32, want32) << "n " << n;

      // Normalisation: the exact Q32 rule, checked against 128-bit-free math
      // (sum < 2^26, inv <= 2^32, product * 16 < 2^62).
      const std::uint64_t sum_w = 1 + static_cast<std::uint64_t>(byte(rng)) * 200;
      const std::uint64_t inv = (std::uint64_t{1} << 32) / sum_w;
      std::vector<std::uint16_t> s16(static_cast<std::size_t>(n) + 1);
      std::vector<std::uint32_t> s32(static_cast<std::size_t>(n) + 1);
      for (std::size_t k = 0; k < s16.size(); ++k) {
        s16[k] = static_cast<std::uint16_t>(std::min<std::uint64_t>(65535, sum_w * byte(rng)));
        s32[k] = static_cast<std::uint32_t>(sum_w * byte(rng));
      }
      std::vector<std::uint16_t> out16(static_cast<std::size_t>(n) + 1, 0xBEEF), out32 = out16;
      ks.normalize_costs_u16(s16.data(), inv, n, out16.data());
      ks.normalize_costs_u32(s32.data(), inv, n, out32.data());
      for (int k = 0; k < n; ++k) {
        const std::uint64_t e16 = (s16[static_cast<std::size_t>(k)] * inv * 16 + (1ull << 31)) >> 32;
        const std::uint64_t e32 = (s32[static_cast<std::size_t>(k)] * inv * 16 + (1ull << 31)) >> 32;
        ASSERT_EQ(out16[static_cast<std::size_t>(k)], e16);
        ASSERT_EQ(out32[static_cast<std::size_t>(k)], e32);
      }
      EXPECT_EQ(out16[static_cast<std::size_t>(n)], 0xBEEF);
      EXPECT_EQ(out32[static_cast<std::size_t>(n)], 0xBEEF);
    }
  }
}

TEST(CostKernelsScalar, NormalizeIsTheRoundedMean) {
  // With sum = W * c exactly, the mean is c: Ca = 16 c for every weight sum.
  const KernelSet& ks = scalar_kernel_set();
  for (std::uint32_t w : {1u, 3u, 7u, 25u, 254u, 961u, 244094u}) {
    for (std::uint32_t c : {0u, 1u, 17u, 128u, 255u}) {
      const std::uint32_t sum = w * c;
      std::uint16_t out = 0;
      ks.normalize_costs_u32(&sum, (std::uint64_t{1} << 32) / w, 1, &out);
      EXPECT_EQ(out, 16 * c) << "w " << w << " c " << c;
    }
  }
  // 1/3 of a grey level = 5.33 in Q4 -> 5; 2/3 = 10.67 -> 11.
  std::uint32_t sums[2] = {1, 2};
  std::uint16_t out[2];
  ks.normalize_costs_u32(sums, (std::uint64_t{1} << 32) / 3, 2, out);
  EXPECT_EQ(out[0], 5);
  EXPECT_EQ(out[1], 11);
}

// ---------------------------------------------------------------- MatchContext

StereoParams small_params(int d_min, int num_disp) {
  StereoParams p = paper_params();  // the AD cost these tests are about
  p.d_min = d_min;
  p.num_disp = num_disp;
  p.cost.truncation = 255;  // tests below state their own truncation
  return p;
}

TEST(MatchContext, ReversedRowsImplementTheClampedBorder) {
  std::mt19937 rng(11);
  for (int d_min : {-7, -1, 0, 3, 40}) {
    for (int num_disp : {1, 5, 33}) {
      const ImageU8 left = random_image(23, 4, rng), right = random_image(23, 4, rng);
      MatchContext ctx(32, 8, small_params(d_min, num_disp), scalar_kernel_set());
      ctx.begin_frame(left.view(), right.view());
      ctx.prepare_right_rows(0, 4);
      for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 23; ++x)
          for (int k = 0; k < num_disp; ++k) {
            const int src = std::clamp(x - d_min - k, 0, 22);
            ASSERT_EQ(ctx.right_rev_row(y)[ctx.rev_offset(x) + k], right.at(src, y))
                << "d_min " << d_min << " D " << num_disp << " x " << x << " k " << k;
          }
    }
  }
}

std::vector<std::uint16_t> aggregate(const ImageU8& left, const ImageU8& right,
                                     const StereoParams& p, int x, int y) {
  MatchContext ctx(left.width, left.height, p, scalar_kernel_set());
  ctx.begin_frame(left.view(), right.view());
  ctx.prepare_right_rows(0, left.height);
  CostScratch scratch(p.num_disp);
  std::vector<std::uint16_t> out(static_cast<std::size_t>(p.num_disp));
  ctx.aggregate_sample(x, y, out.data(), scratch);
  return out;
}

TEST(MatchContext, ConstantImagesGiveTheirTruncatedDifference) {
  const ImageU8 left(9, 7, 1, 100), right(9, 7, 1, 90);
  StereoParams p = small_params(-2, 6);
  for (Weights wts : {Weights::kBox, Weights::kAdaptive}) {
    p.cost.weights = wts;
    for (int trunc : {255, 10, 5}) {
      p.cost.truncation = trunc;
      for (int x : {0, 4, 8}) {
        const auto c = aggregate(left, right, p, x, 0);
        for (std::uint16_t v : c) EXPECT_EQ(v, 16 * std::min(10, trunc));
      }
    }
  }
}

TEST(MatchContext, ClippedBoxWindowAtTheCorner) {
  // 3x3 box at (0, 0) clips to 2x2 pixels: left = [[0, 10], [20, 30]], right
  // all 0, so d = 0 gives (0 + 10 + 20 + 30) / 4 = 15 -> 240 in Q4; d = 1 reads
  // R(clamp(x - 1)) = 0 as well.
  ImageU8 left(4, 4, 1, 0), right(4, 4, 1, 0);
  left.at(1, 0) = 10;
  left.at(0, 1) = 20;
  left.at(1, 1) = 30;
  StereoParams p = small_params(0, 2);
  p.cost.window_w = p.cost.window_h = 3;
  const auto c = aggregate(left, right, p, 0, 0);
  EXPECT_EQ(c[0], 240);
  EXPECT_EQ(c[1], 240);
  // Truncation at 12: (0 + 10 + 12 + 12) / 4 = 8.5 -> 136.
  p.cost.truncation = 12;
  EXPECT_EQ(aggregate(left, right, p, 0, 0)[0], 136);
}

// Every kernel set this CPU runs (the fused window kernels, their register
// blocks, overlapping last block and narrow tails), against the reference.
TEST(MatchContext, EqualsReferenceOnRandomImages) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> side(1, 15), dmin(-6, 6), nd(1, 24);
  const int wide_d[] = {31, 32, 33, 64, 65, 100, 256};
  for (int trial = 0; trial < 200; ++trial) {
    const int w = 2 + side(rng) * 2, h = 2 + side(rng);
    StereoParams p = small_params(dmin(rng), trial % 4 == 3 ? wide_d[trial % 7] : nd(rng));
    p.cost.window_w = 2 * (side(rng) % 16) + 1;
    p.cost.window_h = 2 * (side(rng) % 16) + 1;
    p.cost.truncation = std::uniform_int_distribution<int>(1, 255)(rng);
    p.cost.weights = trial % 2 ? Weights::kAdaptive : Weights::kBox;
    p.cost.asw_gamma_color = std::uniform_int_distribution<int>(1, 40)(rng);
    p.cost.asw_gamma_proximity = std::uniform_int_distribution<int>(1, 200)(rng);
    const ImageU8 left = random_image(w, h, rng), right = random_image(w, h, rng);
    const int y = std::uniform_int_distribution<int>(0, h - 1)(rng);
    std::vector<int> xs;
    for (int x = 0; x < w; ++x) xs.push_back(x);
    const auto ref = reference::aggregated_costs(left, right, y, xs, p);

    for (KernelChoice set : available_kernel_sets()) {
      MatchContext ctx(w + 3, h + 1, p, kernel_set_for(set));
      ctx.begin_frame(left.view(), right.view());
      ctx.prepare_right_rows(0, h);
      CostScratch scratch(p.num_disp);
      std::vector<std::uint16_t> out(static_cast<std::size_t>(p.num_disp));
      for (int x : xs) {
        ctx.aggregate_sample(x, y, out.data(), scratch);
        for (int k = 0; k < p.num_disp; ++k)
          ASSERT_EQ(out[static_cast<std::size_t>(k)], ref[static_cast<std::size_t>(x)][static_cast<std::size_t>(k)])
              << "trial " << trial << " set " << to_string(set) << " x " << x << " k " << k
              << " u16 " << ctx.uses_u16_box();
      }
    }
  }
}

TEST(MatchContext, LaneWidthFollowsTheBound) {
  StereoParams p = small_params(0, 4);
  p.cost.window_w = p.cost.window_h = 15;  // 225 * 255 = 57375 <= 65535
  EXPECT_TRUE(MatchContext(16, 16, p, scalar_kernel_set()).uses_u16_box());
  p.cost.window_w = p.cost.window_h = 17;  // 289 * 255 = 73695 > 65535
  EXPECT_FALSE(MatchContext(16, 16, p, scalar_kernel_set()).uses_u16_box());
  p.cost.truncation = 226;                 // 289 * 226 = 65314
  EXPECT_TRUE(MatchContext(16, 16, p, scalar_kernel_set()).uses_u16_box());
  p.cost.weights = Weights::kAdaptive;
  EXPECT_FALSE(MatchContext(16, 16, p, scalar_kernel_set()).uses_u16_box());

  // The largest window with no truncation goes through the u32 lanes and
  // still gives the exact mean: a 31x31 window of differences 255 -> 4080.
  p = small_params(0, 2);
  p.cost.window_w = p.cost.window_h = 31;
  const ImageU8 left(40, 40, 1, 255), right(40, 40, 1, 0);
  for (std::uint16_t v : aggregate(left, right, p, 20, 20)) EXPECT_EQ(v, 4080);
}

TEST(MatchContext, RejectsBadParametersAndKeepsItsConfiguration) {
  const StereoParams good = small_params(0, 8);
  MatchContext ctx(16, 16, good, scalar_kernel_set());
  auto expect_bad = [&](StereoParams p) {
    EXPECT_THROW(ctx.configure(16, 16, p, scalar_kernel_set()), Error);
  };
  StereoParams p = good;
  p.cost.window_w = 4;
  expect_bad(p);
  p = good;
  p.cost.window_h = 33;
  expect_bad(p);
  p = good;
  p.cost.truncation = 0;
  expect_bad(p);
  p = good;
  p.num_disp = 0;
  expect_bad(p);
  p = good;
  p.num_disp = 257;
  expect_bad(p);
  p = good;
  p.d_min = 2048 - 8 + 1;  // |d_min| + D = 2049
  expect_bad(p);
  p = good;
  p.d_min = -2041;
  expect_bad(p);
  p = good;
  p.dp.lambda_q4 = 32001;
  expect_bad(p);
  p = good;
  p.cost.asw_gamma_color = 0;
  expect_bad(p);
  EXPECT_THROW(ctx.configure(1, 16, good, scalar_kernel_set()), Error);
  EXPECT_THROW(ctx.configure(16, 4097, good, scalar_kernel_set()), Error);
  try {
    p = good;
    p.cost.window_w = 4;
    ctx.configure(16, 16, p, scalar_kernel_set());
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(e.what()).find("window_w = 4"), std::string::npos) << e.what();
  }
  // Still the good configuration.
  EXPECT_EQ(ctx.num_disp(), 8);
  EXPECT_EQ(ctx.params().cost.window_w, 5);
  p = good;
  p.d_min = 2040;  // |d_min| + D = 2048: the largest allowed
  EXPECT_NO_THROW(ctx.configure(16, 16, p, scalar_kernel_set()));
}

TEST(MatchContext, RejectsBadFrames) {
  MatchContext ctx(16, 8, small_params(0, 4), scalar_kernel_set());
  const ImageU8 a(10, 6), b(11, 6), rgb(10, 6, 3), big(17, 6), tiny(1, 6);
  EXPECT_THROW(ctx.begin_frame(a.view(), b.view()), Error);
  EXPECT_THROW(ctx.begin_frame(rgb.view(), rgb.view()), Error);
  EXPECT_THROW(ctx.begin_frame(big.view(), big.view()), Error);
  EXPECT_THROW(ctx.begin_frame(tiny.view(), tiny.view()), Error);
  ImageView<const std::uint8_t> null_view = a.view();
  null_view.data = nullptr;
  EXPECT_THROW(ctx.begin_frame(null_view, a.view()), Error);
  EXPECT_EQ(ctx.width(), 0);  // nothing recorded
  EXPECT_THROW(ctx.prepare_right_rows(0, 1), Error);
  ctx.begin_frame(a.view(), a.view());
  EXPECT_EQ(ctx.width(), 10);
  EXPECT_THROW(ctx.prepare_right_rows(0, 7), Error);
  EXPECT_THROW(ctx.prepare_right_rows(-1, 2), Error);
  EXPECT_NO_THROW(ctx.prepare_right_rows(2, 6));
  MatchContext unconfigured;
  EXPECT_THROW(unconfigured.begin_frame(a.view(), a.view()), Error);
}

}  // namespace
}  // namespace tristereo
