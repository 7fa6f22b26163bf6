// Sub-pixel refinement of a sample's disparity (docs/model.md section 3).
#pragma once

#include <cstdint>

#include "tristereo/fixed_point.hpp"
#include "tristereo/params.hpp"

namespace tristereo {

// Costs are the row DP's aggregated costs (0..4080) or the paths' summed
// costs (0..65534), so 16 |cm - cp| < 2^21 and every intermediate fits int32.

// Offset in Q4 of the vertex of the parabola through (-1, cm), (0, c0), (1, cp):
// (cm - cp) / (2 den) pixels with den = cm + cp - 2 c0, rounded half up in Q4 as
// floor((16 (cm - cp) + den) / (2 den)) and clamped to [-8, 8]; 0 when den <= 0
// (no finite minimum).
inline int subpixel_offset_q4(int cm, int c0, int cp) {
  const int den = cm + cp - 2 * c0;
  if (den <= 0) return 0;
  const int off = static_cast<int>(floor_div(kDispOne * (cm - cp) + den, 2 * den));
  const int half = kDispOne / 2;
  return off < -half ? -half : (off > half ? half : off);
}

// Offset in Q4 of the equiangular fit: the symmetric V (two lines of slopes
// +m and -m) through the three costs, m = max(cm, cp) - c0, whose vertex lies
// (cm - cp) / (2 m) pixels from k; rounded half up in Q4 as
// floor((16 (cm - cp) + m) / (2 m)) and clamped to [-8, 8]; 0 when m <= 0 (c0
// is no lower than both neighbours: no V opens upwards).
inline int equiangular_offset_q4(int cm, int c0, int cp) {
  const int m = (cm > cp ? cm : cp) - c0;
  if (m <= 0) return 0;
  const int off = static_cast<int>(floor_div(kDispOne * (cm - cp) + m, 2 * m));
  const int half = kDispOne / 2;
  return off < -half ? -half : (off > half ? half : off);
}

inline int subpixel_offset_q4(SubpixelFit fit, int cm, int c0, int cp) {
  return fit == SubpixelFit::kEquiangular ? equiangular_offset_q4(cm, c0, cp) : subpixel_offset_q4(cm, c0, cp);
}

}  // namespace tristereo
