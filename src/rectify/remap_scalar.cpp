// The remap kernel's scalar twin (KernelSet::remap_bilinear_row_u8).
#include "src/kernels/kernels_scalar.hpp"

namespace tristereo {

void remap_bilinear_row_u8_scalar(const std::uint8_t* src, std::size_t stride, const std::int16_t* xy,
                                  const std::uint16_t* frac, int n, std::uint8_t* out) {
  for (int i = 0; i < n; ++i) {
    const std::size_t j = static_cast<std::size_t>(i);
    const std::uint8_t* s = src + static_cast<std::size_t>(xy[2 * j + 1]) * stride + static_cast<std::size_t>(xy[2 * j]);
    const std::int32_t fx = frac[j] & 31, fy = frac[j] >> 5;
    const std::int32_t sum = s[0] * (32 - fx) * (32 - fy) + s[1] * fx * (32 - fy) + s[stride] * (32 - fx) * fy +
                             s[stride + 1] * fx * fy;
    out[i] = static_cast<std::uint8_t>((sum + 512) >> 10);
  }
}

}  // namespace tristereo
