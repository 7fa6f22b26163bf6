// Scalar reference of the plane-residual span kernel (see plane_residual.hpp).
#include "src/tritree/plane_residual.hpp"

namespace tristereo {

std::uint64_t plane_residual_sse_span_scalar(const std::uint8_t* row, int x_begin, int x_end,
                                             std::int64_t r_at_x_begin, std::int64_t n_x,
                                             std::int64_t area2) {
  return plane_residual_sse_span_inline(row, x_begin, x_end, r_at_x_begin, n_x, area2);
}

}  // namespace tristereo
