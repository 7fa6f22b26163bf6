// The census cost's box mean from a byte sum by a 15-bit reciprocal.
//
// docs/model.md section 2 defines a sample's cost as the Q4 mean of its box
// sum by the Q32 rule (16 s floor(2^32 / pixels) + 2^31) >> 32. When the
// census's box sums fit a byte, the matcher keeps them as bytes and the path
// kernels take the means in registers as (16 s M + 2^14) >> 15 with M below
// 2^15 (KernelSet::path_steps_u8): one rounding multiply-high per lane on AVX2
// (pmulhrsw) and NEON (vqrdmulh). This file finds an M that gives the Q32
// rule's mean for every sum a box of `pixels` pixels can hold, or reports that
// there is none.
#pragma once

#include <cstdint>

namespace tristereo {

// The Q4 mean of byte sum s by inv_q15 (KernelSet::path_steps_u8's rule).
inline std::uint16_t byte_mean_q4(std::uint32_t s, std::uint32_t inv_q15) {
  return static_cast<std::uint16_t>((16u * s * inv_q15 + 0x4000u) >> 15);
}

// The smallest inv_q15 within 32 of 2^15 / pixels (clamped to 1 .. 32767) for
// which (16 s inv_q15 + 2^14) >> 15 == (16 s floor(2^32 / pixels) + 2^31) >> 32
// for every s in [0, max_sum]; 0 when there is none, or for pixels < 1 or
// max_sum outside 0 .. 255.
std::uint16_t byte_mean_inv_q15(int pixels, int max_sum);

}  // namespace tristereo
