// Sub-pixel refinement of a sample's disparity (docs/model.md section 3).
#pragma once

#include <cstdint>

#include "tristereo/fixed_point.hpp"

namespace tristereo {

// Offset in Q4 of the vertex of the parabola through (-1, cm), (0, c0), (1, cp):
// (cm - cp) / (2 den) pixels with den = cm + cp - 2 c0, rounded half up in Q4 as
// floor((16 (cm - cp) + den) / (2 den)) and clamped to [-8, 8]; 0 when den <= 0
// (no finite minimum). Costs are Q4 aggregated costs (0..4080), so every
// intermediate fits int32.
inline int subpixel_offset_q4(int cm, int c0, int cp) {
  const int den = cm + cp - 2 * c0;
  if (den <= 0) return 0;
  const int off = static_cast<int>(floor_div(kDispOne * (cm - cp) + den, 2 * den));
  const int half = kDispOne / 2;
  return off < -half ? -half : (off > half ? half : off);
}

}  // namespace tristereo
