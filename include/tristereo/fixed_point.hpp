// Fixed-point formats and rounding helpers shared by every stage.
#pragma once

#include <cstdint>

namespace tristereo {

// Disparities are int16 in Q4 (value / 16 = pixels), the OpenCV convention.
constexpr int kDispFracBits = 4;
constexpr int kDispOne = 1 << kDispFracBits;
// Invalid disparity marker in Q4 maps (no valid pixel can reach it: |d| <= 2048).
constexpr std::int16_t kInvalidDispQ4 = INT16_MIN;

// Aggregated costs are mean absolute differences in Q4 (0 .. 255 * 16).
constexpr int kCostFracBits = 4;
constexpr int kMaxCostQ4 = 255 << kCostFracBits;

// floor(a / b) for b > 0 and any sign of a.
constexpr std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  return (a >= 0) ? a / b : -((-a + b - 1) / b);
}

// round(a / b), halves rounded up (towards +inf), b > 0.
constexpr std::int64_t round_div_half_up(std::int64_t a, std::int64_t b) {
  return floor_div(2 * a + b, 2 * b);
}

}  // namespace tristereo
