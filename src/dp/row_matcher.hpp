// Per-row sparse (or dense) dynamic programming with sub-pixel refinement
// (docs/model.md section 3).
//
// One RowMatcher per worker thread: it owns one row's DP tables, allocated at
// configure for the context's maximum width, so match_row never allocates.
// Dense mode is the same call with xs = 0, 1, ..., W - 1.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "src/cost/match_context.hpp"
#include "src/memory/untouched_vector.hpp"

namespace tristereo {

// Wall time a worker spent in match_row, by stage (summed over calls).
struct RowTimes {
  std::int64_t cost_ns = 0;  // aggregate_sample at the samples
  std::int64_t dp_ns = 0;    // recurrence, backtracking, sub-pixel
};

// The DP of one row on precomputed costs (docs/model.md section 3), the core of
// RowMatcher::match_row: cost_q4 + i * stride holds Ca of sample i (D values,
// 0..4080), penalty_by_gap[g] = P(g) (<= kMaxLambdaQ4) for every gap
// xs[i] - xs[i-1]. F_1 = Ca_1; F_i = ks.dp_step(Ca_i, F_{i-1}, P); k_n is the
// smallest argmin of F_n and k_{i-1} = ptr_i(k_i). Writes k_out[0..n).
// Scratch: f_a, f_b (D values each), ptr (n * stride bytes). n >= 1.
void solve_row_dp(const KernelSet& ks, const std::uint16_t* cost_q4, std::size_t stride,
                  const std::int32_t* xs, int n, int num_disp,
                  const std::uint32_t* penalty_by_gap, std::uint32_t* f_a, std::uint32_t* f_b,
                  std::uint8_t* ptr, std::int32_t* k_out);

// Same result as solve_row_dp when every penalty_by_gap[g] used is <=
// kMaxDpPenaltyU16 (then F <= 4080 + 255 * 241 = 65535 fits u16): F_i =
// ks.dp_step_u16(...) is kept for every sample in f_rows + i * stride (row 0 is
// unused: F_1 is cost_q4 itself) and back-pointers are recomputed only where the
// path goes, k_{i-1} = ks.dp_pointer_u16(F_{i-1}, P_i, D, k_i). Scratch: f_rows
// (n * stride values). n >= 1.
void solve_row_dp_u16(const KernelSet& ks, const std::uint16_t* cost_q4, std::size_t stride,
                      const std::int32_t* xs, int n, int num_disp,
                      const std::uint32_t* penalty_by_gap, std::uint16_t* f_rows,
                      std::int32_t* k_out);

class RowMatcher {
 public:
  RowMatcher() = default;
  RowMatcher(int max_width, const StereoParams& params) { configure(max_width, params); }

  // Sizes the tables for max_width samples x params.num_disp and builds the
  // penalty table P(g), g in 1..max_width - 1. Throws Error (matcher unchanged)
  // on max_width outside 2..kMaxImageSide or params that validate_match_params
  // rejects.
  void configure(int max_width, const StereoParams& params);
  // Same, for ctx's maximum width and parameters.
  void configure(const MatchContext& ctx) { configure(ctx.max_width(), ctx.params()); }

  // Disparities (Q4) of the samples xs[0..n) of row y, written to
  // disp_q4_out[0..n):
  //  - Ca at each sample via ctx.aggregate_sample (right rows of the window
  //    must be prepared),
  //  - F_1 = Ca_1, F_i = dp_step(Ca_i, F_{i-1}, P(x_i - x_{i-1})),
  //  - k_n = smallest argmin F_n, back-pointers for the rest,
  //  - disp = 16 (d_min + k) + sub-pixel offset (when params.dp.subpixel).
  // ctx must have the parameters this matcher was configured with (checked:
  // D, d_min, DP parameters, frame width <= max width). Throws Error (output
  // untouched) unless y is a row of the current frame, 0 <= n <= width and xs
  // is strictly increasing in [0, W). Costs of all samples are aggregated
  // first, then the DP runs; `times`, when given, accumulates both stages.
  void match_row(const MatchContext& ctx, int y, const std::int32_t* xs, int n,
                 std::int16_t* disp_q4_out, RowTimes* times = nullptr);

  // Aggregated costs (D values, Q4) of sample i of the last match_row call.
  const std::uint16_t* sample_costs_q4(int i) const {
    return costs_.data() + static_cast<std::size_t>(i) * cost_stride_;
  }
  // Disparity index k (0..D-1) chosen for sample i in the last match_row call.
  int sample_index(int i) const { return index_[static_cast<std::size_t>(i)]; }

  // Bytes of the matcher's buffers (allocated capacities).
  std::size_t working_memory_bytes() const;

 private:
  int num_disp_ = 0;
  int max_samples_ = 0;
  StereoParams params_;
  std::size_t cost_stride_ = 0;          // D rounded up, with kernel slack
  std::vector<std::uint32_t> penalty_;   // P(g), g in 0..max_width - 1
  // The per-sample tables are written before they are read, sample by sample
  // (a sparse row touches only its samples' part): allocated untouched.
  UntouchedVector<std::uint16_t> costs_;  // max_samples x cost_stride_
  // lambda_q4 <= kMaxDpPenaltyU16: the u16 DP (f_rows_), else the u32 one
  // (ptr_, f_prev_, f_cur_); only the chosen path's buffers are allocated.
  bool u16_path_ = false;
  UntouchedVector<std::uint16_t> f_rows_;  // max_samples x cost_stride_ F values (u16 path)
  UntouchedVector<std::uint8_t> ptr_;      // max_samples x cost_stride_ back-pointers
  std::vector<std::uint32_t> f_prev_, f_cur_;
  UntouchedVector<std::int32_t> index_;  // chosen k per sample
  CostScratch scratch_;
};

}  // namespace tristereo
