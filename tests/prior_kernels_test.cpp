// The support prior's kernels (docs/model.md section 6b): every compiled SIMD
// set against the scalar twins on random and saturating inputs for every D
// from 1 to 256 (and every k of the data rival), and the property the prior
// relies on: winner_u16 on the saturated sums finds the exact winner of the
// unsaturated ones, and their rival whenever it is below 65535.
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

class PriorKernels : public ::testing::TestWithParam<KernelChoice> {
 protected:
  void SetUp() override { TRISTEREO_SKIP_UNLESS_RUNNABLE(GetParam()); }
  const KernelSet& simd() const { return kernel_set_for(GetParam()); }
};

TEST(PriorKernelScalar, SaturatesAt65535) {
  const std::uint16_t total[4] = {0, 65534, 65535, 30000};
  const std::uint16_t penalty[4] = {7, 1, 0, 40000};
  std::uint16_t out[4] = {};
  add_saturate_u16_scalar(total, penalty, 4, out);
  EXPECT_EQ(out[0], 7);
  EXPECT_EQ(out[1], 65535);
  EXPECT_EQ(out[2], 65535);
  EXPECT_EQ(out[3], 65535);
}

TEST_P(PriorKernels, AddSaturateEqualsScalar) {
  std::mt19937 rng(40);
  for (int n = 1; n <= 256; ++n)
    for (int trial = 0; trial < 4; ++trial) {
      // trial 0: small sums; 1: everything; 2, 3: near the top, most saturating.
      std::uniform_int_distribution<int> v(trial == 0 ? 0 : trial == 1 ? 0 : 30000, trial == 0 ? 300 : 65535);
      std::vector<std::uint16_t> total(static_cast<std::size_t>(n)), penalty(total.size());
      for (auto& x : total) x = static_cast<std::uint16_t>(v(rng));
      for (auto& x : penalty) x = static_cast<std::uint16_t>(v(rng));
      std::vector<std::uint16_t> a(total.size() + 1, 0x1234), b = a;
      simd().add_saturate_u16(total.data(), penalty.data(), n, a.data());
      add_saturate_u16_scalar(total.data(), penalty.data(), n, b.data());
      ASSERT_EQ(a, b) << "n=" << n << " trial=" << trial;  // the guard past n untouched too
    }
}

// The data rival at the prior's winner: every k of every D, ties and the
// blocks' partial tail included.
TEST_P(PriorKernels, MinOutsideEqualsScalar) {
  std::mt19937 rng(42);
  for (int n = 1; n <= 256; ++n)
    for (int trial = 0; trial < 3; ++trial) {
      std::uniform_int_distribution<int> v(0, trial == 0 ? 3 : 65535);
      std::vector<std::uint16_t> total(static_cast<std::size_t>(n));
      for (auto& x : total) x = static_cast<std::uint16_t>(v(rng));
      for (int k = 0; k < n; ++k) {
        std::vector<std::uint16_t> t = total;
        if (trial == 2) {  // the lowest values at k and beside it: they must be skipped
          t[static_cast<std::size_t>(k)] = 0;
          if (k > 0) t[static_cast<std::size_t>(k - 1)] = 0;
          if (k + 1 < n) t[static_cast<std::size_t>(k + 1)] = 0;
        }
        const std::uint16_t want = min_outside_u16_scalar(t.data(), n, k);
        ASSERT_EQ(simd().min_outside_u16(t.data(), n, k), want) << "n=" << n << " k=" << k << " trial=" << trial;
        std::uint16_t brute = 0xFFFF;
        for (int j = 0; j < n; ++j)
          if (std::abs(j - k) > 1) brute = std::min(brute, t[static_cast<std::size_t>(j)]);
        ASSERT_EQ(want, brute);
      }
    }
}

// The prior's use: S'(k) = S(k) + lambda min(|k - kp|, T) with S(k) <= 65534.
TEST_P(PriorKernels, WinnerOfSaturatedSumsIsExact) {
  std::mt19937 rng(41);
  for (int n : {1, 2, 3, 4, 7, 16, 17, 31, 64, 80, 129, 256})
    for (int trial = 0; trial < 200; ++trial) {
      const int lambda = std::uniform_int_distribution<int>(1, 16000)(rng);
      const int trunc = std::uniform_int_distribution<int>(1, 256)(rng);
      const int kp = std::uniform_int_distribution<int>(0, n - 1)(rng);
      std::uniform_int_distribution<int> v(trial % 2 ? 60000 : 0, 65534);
      std::vector<std::uint16_t> s(static_cast<std::size_t>(n)), pen(s.size()), out(s.size());
      std::vector<std::uint32_t> exact(s.size());
      for (int k = 0; k < n; ++k) {
        s[static_cast<std::size_t>(k)] = static_cast<std::uint16_t>(v(rng));
        const std::uint32_t p = static_cast<std::uint32_t>(lambda) * static_cast<std::uint32_t>(std::min(std::abs(k - kp), trunc));
        pen[static_cast<std::size_t>(k)] = static_cast<std::uint16_t>(std::min<std::uint32_t>(p, 0xFFFF));
        exact[static_cast<std::size_t>(k)] = s[static_cast<std::size_t>(k)] + p;
      }
      simd().add_saturate_u16(s.data(), pen.data(), n, out.data());
      std::uint16_t rival = 0;
      const int k = simd().winner_u16(out.data(), n, &rival, nullptr, nullptr);
      const int k_exact = static_cast<int>(std::min_element(exact.begin(), exact.end()) - exact.begin());
      ASSERT_EQ(k, k_exact) << "n=" << n << " trial=" << trial;
      std::uint32_t r_exact = 0xFFFFFFFFu;
      for (int j = 0; j < n; ++j)
        if (std::abs(j - k) > 1) r_exact = std::min(r_exact, exact[static_cast<std::size_t>(j)]);
      if (r_exact < 0xFFFFu) {
        ASSERT_EQ(rival, r_exact) << "n=" << n << " trial=" << trial;
      } else {
        ASSERT_EQ(rival, 0xFFFF) << "n=" << n << " trial=" << trial;
      }
    }
}

INSTANTIATE_TEST_SUITE_P(Sets, PriorKernels, ::testing::ValuesIn(test::simd_kernel_params()),
                         test::KernelParamName());
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(PriorKernels);

}  // namespace
}  // namespace tristereo
