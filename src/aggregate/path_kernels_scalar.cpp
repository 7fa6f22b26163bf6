// Scalar path-aggregation and winner kernels (docs/model.md sections 3b, 6).
#include <cstdint>

#include "src/cost/byte_means.hpp"
#include "src/kernels/kernels_scalar.hpp"
#include "tristereo/params.hpp"

namespace tristereo {

std::uint16_t path_step_u16_scalar(const std::uint16_t* cost, const std::uint16_t* prev,
                                   std::uint16_t prev_min, std::uint16_t p1, std::uint16_t p2,
                                   int n, std::uint16_t* out, std::uint16_t* sum,
                                   int accumulate) {
  // prev[-1] and prev[n] are 0xFFFF guards: with the saturating add they never
  // win the minimum, so the edges of the disparity range need no branch.
  const std::uint32_t jump = std::uint32_t{prev_min} + p2;
  std::uint16_t m = 0xFFFF;
  for (int k = 0; k < n; ++k) {
    const std::uint32_t down = std::uint32_t{prev[k - 1]} + p1;
    const std::uint32_t up = std::uint32_t{prev[k + 1]} + p1;
    std::uint32_t best = prev[k];
    if (down < best) best = down;
    if (up < best) best = up;
    if (jump < best) best = jump;
    const auto v = static_cast<std::uint16_t>(cost[k] + best - prev_min);
    out[k] = v;
    sum[k] = static_cast<std::uint16_t>(accumulate ? sum[k] + v : v);
    if (v < m) m = v;
  }
  return m;
}

void path_steps_u16_scalar(const std::uint16_t* cost, const std::uint16_t* const* prev,
                           const std::uint16_t* prev_min, const std::uint16_t* p1, const std::uint16_t* p2,
                           int count, int n, std::uint16_t* const* out, std::uint16_t* sum, int accumulate,
                           std::uint16_t* mins) {
  for (int r = 0; r < count; ++r)
    mins[r] = path_step_u16_scalar(cost, prev[r], prev_min[r], p1[r], p2[r], n, out[r], sum, r == 0 ? accumulate : 1);
}

void path_steps_u8_scalar(const std::uint8_t* cost_sums, std::uint16_t inv_q15, const std::uint16_t* const* prev,
                          const std::uint16_t* prev_min, const std::uint16_t* p1, const std::uint16_t* p2, int count,
                          int n, std::uint16_t* const* out, std::uint16_t* sum, int accumulate, std::uint16_t* mins) {
  std::uint16_t cost[kMaxNumDisp];
  for (int k = 0; k < n; ++k) cost[k] = byte_mean_q4(cost_sums[k], inv_q15);
  path_steps_u16_scalar(cost, prev, prev_min, p1, p2, count, n, out, sum, accumulate, mins);
}

void lr_min_u16_scalar(const std::uint16_t* total, int n, std::uint16_t* best_cost,
                       std::uint16_t* best_k) {
  for (int k = 0; k < n; ++k)
    if (total[k] < best_cost[k]) {
      best_cost[k] = total[k];
      best_k[k] = static_cast<std::uint16_t>(k);
    }
}

std::uint16_t min_outside_u16_scalar(const std::uint16_t* total, int n, int k) {
  std::uint16_t m = 0xFFFF;
  for (int j = 0; j < n; ++j)
    if ((j < k - 1 || j > k + 1) && total[j] < m) m = total[j];
  return m;
}

int winner_u16_scalar(const std::uint16_t* total, int n, std::uint16_t* rival, std::uint16_t* best_cost,
                      std::uint16_t* best_k) {
  int k = 0;
  for (int j = 1; j < n; ++j)
    if (total[j] < total[k]) k = j;
  if (rival != nullptr) *rival = min_outside_u16_scalar(total, n, k);
  if (best_cost != nullptr) lr_min_u16_scalar(total, n, best_cost, best_k);
  return k;
}

}  // namespace tristereo
