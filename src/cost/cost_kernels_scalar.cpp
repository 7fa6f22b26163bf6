// Scalar cost kernels (docs/model.md section 2).
#include <algorithm>
#include <cstdlib>

#include "src/kernels/kernels_scalar.hpp"

namespace tristereo {

namespace {
// Rounding constant and shift of the Q32 reciprocal normalisation.
constexpr int kInvShift = 32;
constexpr std::uint64_t kInvHalf = std::uint64_t{1} << (kInvShift - 1);
constexpr int kCostScale = 16;  // Q4

inline std::uint8_t truncated_abs_diff(std::uint8_t a, std::uint8_t b, std::uint8_t trunc) {
  const int d = a > b ? a - b : b - a;
  return static_cast<std::uint8_t>(d < trunc ? d : trunc);
}
}  // namespace

void accumulate_abs_diff_u16_scalar(const std::uint8_t* right_rev, std::uint8_t left,
                                    std::uint8_t trunc, int n, std::uint16_t* acc) {
  for (int k = 0; k < n; ++k)
    acc[k] = static_cast<std::uint16_t>(acc[k] + truncated_abs_diff(left, right_rev[k], trunc));
}

void accumulate_abs_diff_weighted_u32_scalar(const std::uint8_t* right_rev, std::uint8_t left,
                                             std::uint16_t weight, std::uint8_t trunc, int n,
                                             std::uint32_t* acc) {
  for (int k = 0; k < n; ++k)
    acc[k] += std::uint32_t{weight} * truncated_abs_diff(left, right_rev[k], trunc);
}

void aggregate_window_box_u16_scalar(const std::uint8_t* const* right_rev,
                                     const std::uint8_t* left, int count, std::uint8_t trunc,
                                     int n, std::uint16_t* sum) {
  std::fill(sum, sum + n, std::uint16_t{0});
  for (int i = 0; i < count; ++i) accumulate_abs_diff_u16_scalar(right_rev[i], left[i], trunc, n, sum);
}

void aggregate_window_weighted_u32_scalar(const std::uint8_t* const* right_rev,
                                          const std::uint8_t* left, const std::uint16_t* weight,
                                          int count, std::uint8_t trunc, int n,
                                          std::uint32_t* sum) {
  std::fill(sum, sum + n, 0u);
  for (int i = 0; i < count; ++i)
    accumulate_abs_diff_weighted_u32_scalar(right_rev[i], left[i], weight[i], trunc, n, sum);
}

// sum * inv_q32 * 16 < 255 * 2^36: the product fits 64 bits for any weight sum.
void normalize_costs_u16_scalar(const std::uint16_t* sum, std::uint64_t inv_q32, int n,
                                std::uint16_t* cost_q4) {
  for (int k = 0; k < n; ++k)
    cost_q4[k] = static_cast<std::uint16_t>((sum[k] * inv_q32 * kCostScale + kInvHalf) >> kInvShift);
}

void normalize_costs_u8_scalar(const std::uint8_t* sum, std::uint64_t inv_q32, int n, std::uint16_t* cost_q4) {
  for (int k = 0; k < n; ++k)
    cost_q4[k] = static_cast<std::uint16_t>((sum[k] * inv_q32 * kCostScale + kInvHalf) >> kInvShift);
}

void normalize_costs_u32_scalar(const std::uint32_t* sum, std::uint64_t inv_q32, int n,
                                std::uint16_t* cost_q4) {
  for (int k = 0; k < n; ++k)
    cost_q4[k] = static_cast<std::uint16_t>((sum[k] * inv_q32 * kCostScale + kInvHalf) >> kInvShift);
}

}  // namespace tristereo
