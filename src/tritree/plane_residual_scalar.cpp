// Scalar reference of the plane-residual span kernel (see plane_residual.hpp).
#include "src/tritree/plane_residual.hpp"

namespace tristereo {

std::uint64_t plane_residual_sse_span_scalar(const std::uint8_t* row, int x_begin, int x_end,
                                             std::int64_t r_at_x_begin, std::int64_t n_x,
                                             std::int64_t area2) {
  std::uint64_t sse = 0;
  std::int64_t r_plane = r_at_x_begin;  // residual without the pixel term
  for (int x = x_begin; x < x_end; ++x) {
    const std::int64_t r = r_plane + area2 * row[x];
    sse += static_cast<std::uint64_t>(r * r);
    r_plane += n_x;
  }
  return sse;
}

}  // namespace tristereo
