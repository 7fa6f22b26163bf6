// Scalar DP step (docs/model.md section 3).
//
// The L1 min-convolution g[k] = min_j prev[j] + P|k - j| is computed in O(n) by a
// forward and a backward pass over packed keys (value << 8 | j): adding P << 8
// to a key raises its value and keeps its index, and min() over keys picks the
// smallest value and, among equal values, the smallest j, which is the model's
// tie rule. Values stay below 2^24 (see KernelSet::dp_step).
#include <cstdint>

#include "src/kernels/kernels_scalar.hpp"

namespace tristereo {

namespace {
constexpr int kIndexBits = 8;
constexpr std::uint32_t kIndexMask = (1u << kIndexBits) - 1;
}  // namespace

void dp_step_scalar(const std::uint16_t* cost_q4, const std::uint32_t* prev,
                    std::uint32_t penalty, int n, std::uint32_t* out, std::uint8_t* ptr) {
  const std::uint32_t step = penalty << kIndexBits;
  // Forward pass: best key among j <= k. `out` holds keys until the last loop.
  std::uint32_t run = (prev[0] << kIndexBits) | 0u;
  out[0] = run;
  for (int k = 1; k < n; ++k) {
    const std::uint32_t own = (prev[k] << kIndexBits) | static_cast<std::uint32_t>(k);
    run += step;
    run = own < run ? own : run;
    out[k] = run;
  }
  // Backward pass: best key among all j.
  run = out[n - 1];
  for (int k = n - 2; k >= 0; --k) {
    run += step;
    run = out[k] < run ? out[k] : run;
    out[k] = run;
  }
  std::uint32_t min_g = out[0] >> kIndexBits;
  for (int k = 1; k < n; ++k) {
    const std::uint32_t g = out[k] >> kIndexBits;
    min_g = g < min_g ? g : min_g;
  }
  for (int k = 0; k < n; ++k) {
    ptr[k] = static_cast<std::uint8_t>(out[k] & kIndexMask);
    out[k] = cost_q4[k] + (out[k] >> kIndexBits) - min_g;
  }
}

// The u16 twin without back-pointers: the same two passes on plain values
// (the tie rule matters only for pointers, which dp_pointer_u16 recomputes).
void dp_step_u16_scalar(const std::uint16_t* cost_q4, const std::uint16_t* prev,
                        std::uint32_t penalty, int n, std::uint16_t* out) {
  // Every value is <= 0xFFFF, so a step of 0xFFFF or more never wins a min:
  // clamping it keeps the u32 sums exact.
  const std::uint32_t step = penalty < 0xFFFFu ? penalty : 0xFFFFu;
  std::uint32_t run = prev[0];
  out[0] = static_cast<std::uint16_t>(run);
  for (int k = 1; k < n; ++k) {
    const std::uint32_t own = prev[k];
    run += step;
    run = own < run ? own : run;
    out[k] = static_cast<std::uint16_t>(run);
  }
  run = out[n - 1];
  std::uint32_t min_g = run;
  for (int k = n - 2; k >= 0; --k) {
    run += step;
    run = out[k] < run ? out[k] : run;
    out[k] = static_cast<std::uint16_t>(run);
    min_g = run < min_g ? run : min_g;
  }
  for (int k = 0; k < n; ++k)
    out[k] = static_cast<std::uint16_t>(cost_q4[k] + out[k] - min_g);
}

int dp_pointer_u16_scalar(const std::uint16_t* prev, std::uint32_t penalty, int n, int k) {
  int best_j = 0;
  std::uint64_t best = prev[0] + std::uint64_t{penalty} * static_cast<std::uint64_t>(k);
  for (int j = 1; j < n; ++j) {
    const std::uint64_t dist = static_cast<std::uint64_t>(j < k ? k - j : j - k);
    const std::uint64_t v = prev[j] + std::uint64_t{penalty} * dist;
    if (v < best) {  // strict: the smallest minimising j wins ties
      best = v;
      best_j = j;
    }
  }
  return best_j;
}

}  // namespace tristereo
