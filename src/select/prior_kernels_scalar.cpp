// Scalar support-prior kernel (docs/model.md section 6b).
#include <cstdint>

#include "src/kernels/kernels_scalar.hpp"

namespace tristereo {

void add_saturate_u16_scalar(const std::uint16_t* total, const std::uint16_t* penalty, int n,
                             std::uint16_t* out) {
  for (int k = 0; k < n; ++k) {
    const std::uint32_t v = std::uint32_t{total[k]} + penalty[k];
    out[k] = static_cast<std::uint16_t>(v < 0xFFFFu ? v : 0xFFFFu);
  }
}

}  // namespace tristereo
