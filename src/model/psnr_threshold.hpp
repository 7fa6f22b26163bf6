// The tritree's PSNR threshold as an exact integer (docs/model.md section 1).
//
// A triangle fails the plane-fit test when PSNR < eps, i.e. when
// MSE > 255^2 * 10^(-eps / 10 dB). mse_threshold_q8() returns that MSE bound in
// Q8 (value / 256 = squared intensity levels), computed with integer
// arithmetic only, so x86, ARM, the integer path and the float reference all
// get the same number without depending on libm's pow().
//
// Header-only on purpose: the float reference library (src/reference) uses it
// and must not link the `tristereo` library.
#pragma once

#include <cstdint>

namespace tristereo {

// 10^(-0.01) in Q31: one 0.1 dB step of the threshold. Committed constant;
// tests/tritree_test.cpp regenerates it with long double and checks it.
constexpr std::uint64_t kPsnrStepQ31 = 2098600952u;  // round(2^31 * 10^(-1/100))
constexpr int kQ31Bits = 31;
constexpr std::uint64_t kQ31One = std::uint64_t{1} << kQ31Bits;
constexpr std::uint64_t kQ31Half = std::uint64_t{1} << (kQ31Bits - 1);
// 256 * 255^2: MSE of a full-scale error, in Q8.
constexpr std::uint64_t kFullScaleMseQ8 = 256u * 255u * 255u;

// (a * b) in Q31 with round half up. a, b <= 2^31, so a * b < 2^62 fits.
constexpr std::uint64_t mul_q31_round(std::uint64_t a, std::uint64_t b) {
  return (a * b + kQ31Half) >> kQ31Bits;
}

// round(256 * 255^2 * 10^(-psnr_deci_db / 100)) for psnr_deci_db >= 0 (0.1 dB
// units; the model uses 100..700). The definition is this exact sequence:
// p = kPsnrStepQ31^psnr_deci_db by right-to-left square-and-multiply (result
// multiplied by the current square for each set bit, LSB first, every product
// rounded by mul_q31_round), then (p * 256 * 255^2 + 2^30) >> 31.
// Differs from the real value by < 0.5 + 2e-8 relative (checked for 100..700).
// Range: 1 .. 16646400; 70 dB gives 2, 40 dB gives 1665.
constexpr std::uint64_t mse_threshold_q8(int psnr_deci_db) {
  std::uint64_t result = kQ31One;
  std::uint64_t square = kPsnrStepQ31;
  for (unsigned n = static_cast<unsigned>(psnr_deci_db); n != 0; n >>= 1) {
    if (n & 1u) result = mul_q31_round(result, square);
    square = mul_q31_round(square, square);
  }
  // result <= 2^31 and kFullScaleMseQ8 < 2^24: the product stays below 2^55.
  return (result * kFullScaleMseQ8 + kQ31Half) >> kQ31Bits;
}

}  // namespace tristereo
