// The tritree's hot loop: sum of squared plane residuals over one pixel span.
//
// For a triangle with plane normal n = (n_x, n_y, area2) (docs/model.md
// section 1), the residual of pixel x on a row is
//   r(x) = r_at_x_begin + n_x * (x - x_begin) + area2 * row[x],
// where r_at_x_begin already holds n_x (x_begin - Ax) + n_y (y - Ay) - area2 I_A.
// Bounds (area2 <= 2048 when the test runs, pixels owned by the triangle):
// |r| <= 255 * area2 < 2^19, so r^2 < 2^38 and a triangle's sum (<= 7168
// pixels) stays below 2^52; the uint64 accumulator never wraps.
// A SIMD twin must have this exact signature and return the identical sum.
#pragma once

#include <cstdint>

namespace tristereo {

// Sum of r(x)^2 for x in [x_begin, x_end). row points at pixel 0 of the row.
std::uint64_t plane_residual_sse_span_scalar(const std::uint8_t* row, int x_begin, int x_end,
                                             std::int64_t r_at_x_begin, std::int64_t n_x,
                                             std::int64_t area2);

// The same loop, inline: the tritree's spans are short (a few pixels), so a
// call per span costs as much as the span itself.
inline std::uint64_t plane_residual_sse_span_inline(const std::uint8_t* row, int x_begin,
                                                    int x_end, std::int64_t r_at_x_begin,
                                                    std::int64_t n_x, std::int64_t area2) {
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
