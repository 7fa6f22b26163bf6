// Exponential-decay look-up tables for the adaptive support weights.
//
// docs/model.md section 2 defines ws(t) = round(255 exp(-t / gamma_color)) and
// wp(s) = round(255 exp(-s / gamma_prox)). libm's exp() may differ by an ulp
// between x86 and ARM and flip a rounding, so the tables are built with integer
// arithmetic only; every platform produces the same bytes. Header-only so the
// float reference (which must not link `tristereo`) uses the very same tables.
#pragma once

#include <cstdint>

namespace tristereo {

// Scale of the intermediate fixed-point values.
constexpr int kExpBaseBits = 62;   // e^{-1/gamma} series, Q62 (fits uint64)
constexpr int kExpPowBits = 31;    // powers b^t, Q31 (products of two fit uint64)

// e^{-1/gamma} in Q31, gamma >= 1: the alternating Taylor series
// sum_n (-1)^n / (gamma^n n!) in Q62, each term rounded to nearest, then
// rounded to Q31. The Q62 sum is within ~30 ulp(Q62) of the truth, far below
// the final Q31 rounding.
constexpr std::uint64_t exp_neg_inv_q31(int gamma) {
  const std::uint64_t one_q62 = std::uint64_t{1} << kExpBaseBits;
  std::uint64_t term = one_q62;
  std::uint64_t sum = one_q62;  // the series of 0 < x <= 1 stays in (0.36, 1]
  for (std::uint64_t n = 1; term != 0; ++n) {
    const std::uint64_t div = static_cast<std::uint64_t>(gamma) * n;
    term = (term + div / 2) / div;
    if (n % 2 == 1)
      sum -= term;
    else
      sum += term;
  }
  const int drop = kExpBaseBits - kExpPowBits;
  return (sum + (std::uint64_t{1} << (drop - 1))) >> drop;
}

// out[t] = round(255 * exp(-t / gamma)) for t in [0, count), gamma >= 1,
// count >= 0. Powers b^t are formed by repeated Q31 multiplication with
// rounding: the accumulated error stays below t ulp(Q31), so each entry is
// within 1 of the exact rounding (tests/cost_test.cpp checks this for the
// configured ranges) and bit-identical on every platform.
constexpr void exp_decay_table_u8(int gamma, int count, std::uint8_t* out) {
  const std::uint64_t base_q31 = exp_neg_inv_q31(gamma);
  const std::uint64_t half_q31 = std::uint64_t{1} << (kExpPowBits - 1);
  std::uint64_t pow_q31 = std::uint64_t{1} << kExpPowBits;  // b^0 = 1
  for (int t = 0; t < count; ++t) {
    out[t] = static_cast<std::uint8_t>((255 * pow_q31 + half_q31) >> kExpPowBits);
    pow_q31 = (pow_q31 * base_q31 + half_q31) >> kExpPowBits;
  }
}

}  // namespace tristereo
