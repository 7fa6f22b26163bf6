// The 15-bit reciprocals that replace the model's Q32 mean of census byte sums
// (src/cost/byte_means.hpp), against the Q32 rule itself.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "src/cost/byte_means.hpp"
#include "src/kernels/kernels_scalar.hpp"

namespace tristereo {
namespace {

// (16 s M + 2^14) >> 15 for s = 0 .. max_sum, and the model's means of the same sums.
void expect_model_means(int pixels, int max_sum, std::uint16_t inv_q15) {
  std::vector<std::uint8_t> sums;
  for (int s = 0; s <= max_sum; ++s) sums.push_back(static_cast<std::uint8_t>(s));
  const int n = static_cast<int>(sums.size());
  std::vector<std::uint16_t> model(sums.size());
  normalize_costs_u8_scalar(sums.data(), (std::uint64_t{1} << 32) / static_cast<std::uint64_t>(pixels), n, model.data());
  for (int s = 0; s < n; ++s)
    ASSERT_EQ((static_cast<std::uint32_t>(s) * 16u * inv_q15 + 0x4000u) >> 15, model[static_cast<std::size_t>(s)])
        << pixels << " pixels, sum " << s << ", M " << inv_q15;
}

// The default census (5 x 5: 24 bits) in the default 3 x 3 box, clipped at the
// borders to 1..3 x 1..3 pixels: every size has one, and it gives the model's means.
TEST(ByteMeans, EveryClippedBoxOfTheDefaultCensusHasOne) {
  for (int a = 1; a <= 3; ++a)
    for (int b = 1; b <= 3; ++b) {
      const int pixels = a * b, max_sum = 24 * pixels;
      const std::uint16_t m = byte_mean_inv_q15(pixels, max_sum);
      ASSERT_NE(m, 0) << pixels << " pixels";
      expect_model_means(pixels, max_sum, m);
    }
  // The smallest that works (a brute-force search over all of them).
  EXPECT_EQ(byte_mean_inv_q15(9, 216), 3641);
  EXPECT_EQ(byte_mean_inv_q15(6, 144), 5459);
  EXPECT_EQ(byte_mean_inv_q15(1, 24), 32736);
}

TEST(ByteMeans, AnyBoxWhoseSumsFitAByte) {
  for (int pixels = 1; pixels <= 255; ++pixels)
    for (int bits : {8, 24, 48}) {
      if (bits * pixels > 255) continue;
      const std::uint16_t m = byte_mean_inv_q15(pixels, bits * pixels);
      if (m != 0) expect_model_means(pixels, bits * pixels, m);
    }
}

// A 3 x 3 census in a 5 x 5 box (sums up to 200): no 15-bit reciprocal near
// 2^15 / 25 gives every mean, so the matcher keeps Q4 costs there.
TEST(ByteMeans, NoneForTwentyFivePixelsOfEightBits) {
  EXPECT_EQ(byte_mean_inv_q15(25, 200), 0);
  // A wrong M is caught: 2^15 / 25 is off for some sum below 200.
  const std::uint32_t near = (1u << 15) / 25;
  bool differs = false;
  for (std::uint32_t s = 0; s <= 200; ++s)
    differs |= ((16u * s * near + 0x4000u) >> 15) != ((16u * s * ((std::uint64_t{1} << 32) / 25) + (std::uint64_t{1} << 31)) >> 32);
  EXPECT_TRUE(differs);
}

TEST(ByteMeans, OutsideItsRangeItGivesNone) {
  EXPECT_EQ(byte_mean_inv_q15(0, 10), 0);
  EXPECT_EQ(byte_mean_inv_q15(1, 256), 0);
  EXPECT_EQ(byte_mean_inv_q15(9, -1), 0);
}

}  // namespace
}  // namespace tristereo
