#include "src/dp/row_matcher.hpp"

#include <string>
#include <utility>

#include "platform/clock.hpp"
#include "src/dp/penalty.hpp"
#include "src/memory/capacity_bytes.hpp"
#include "src/dp/subpixel.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

namespace {
constexpr std::size_t kKernelSlack = 64;  // SIMD twins may round D up to a vector
}

void RowMatcher::configure(int max_width, const StereoParams& params) {
  if (max_width < 2 || max_width > kMaxImageSide)
    throw Error(ErrorCode::kInvalidArgument, "max_width = " + std::to_string(max_width) +
                                                 " is outside 2.." + std::to_string(kMaxImageSide));
  validate_match_params(params);
  const int d = params.num_disp;
  const int n_max = max_width;
  const std::size_t stride = (static_cast<std::size_t>(d) + kKernelSlack + 63) / 64 * 64;
  std::vector<std::uint32_t> penalty;
  // Gaps are 1..W-1 <= max_width - 1; the table is indexed by the gap directly.
  fill_penalty_table(params.dp.lambda_q4, params.dp.gap, n_max - 1, penalty);
  UntouchedVector<std::uint16_t> costs(stride * n_max);
  // Every P(g) is <= lambda (gap_penalty_q4), so lambda decides the F width.
  const bool u16_path = static_cast<std::uint32_t>(params.dp.lambda_q4) <= kMaxDpPenaltyU16;
  UntouchedVector<std::uint16_t> f_rows(u16_path ? stride * n_max : 0);
  UntouchedVector<std::uint8_t> ptr(u16_path ? 0 : stride * n_max);
  std::vector<std::uint32_t> f_prev(u16_path ? 0 : stride), f_cur(u16_path ? 0 : stride);
  UntouchedVector<std::int32_t> index(n_max);
  CostScratch scratch(d);

  num_disp_ = d;
  max_samples_ = n_max;
  params_ = params;
  cost_stride_ = stride;
  penalty_ = std::move(penalty);
  costs_ = std::move(costs);
  u16_path_ = u16_path;
  f_rows_ = std::move(f_rows);
  ptr_ = std::move(ptr);
  f_prev_ = std::move(f_prev);
  f_cur_ = std::move(f_cur);
  index_ = std::move(index);
  scratch_ = std::move(scratch);
}

std::size_t RowMatcher::working_memory_bytes() const {
  return capacity_bytes(penalty_) + capacity_bytes(costs_) + capacity_bytes(f_rows_) +
         capacity_bytes(ptr_) + capacity_bytes(f_prev_) + capacity_bytes(f_cur_) +
         capacity_bytes(index_) + scratch_.working_memory_bytes();
}

void solve_row_dp(const KernelSet& ks, const std::uint16_t* cost_q4, std::size_t stride,
                  const std::int32_t* xs, int n, int num_disp,
                  const std::uint32_t* penalty_by_gap, std::uint32_t* f_a, std::uint32_t* f_b,
                  std::uint8_t* ptr, std::int32_t* k_out) {
  const int d = num_disp;
  std::uint32_t* prev = f_a;
  std::uint32_t* cur = f_b;
  // Forward pass: F_1 = Ca_1, then the O(D) min-convolution step per sample.
  for (int k = 0; k < d; ++k) prev[k] = cost_q4[k];
  for (int i = 1; i < n; ++i) {
    ks.dp_step(cost_q4 + i * stride, prev, penalty_by_gap[xs[i] - xs[i - 1]], d, cur,
               ptr + i * stride);
    std::swap(prev, cur);
  }
  // Smallest argmin of F_n, then back-pointers.
  int k = 0;
  for (int j = 1; j < d; ++j)
    if (prev[j] < prev[k]) k = j;
  for (int i = n - 1; i >= 0; --i) {
    k_out[i] = k;
    if (i > 0) k = ptr[i * stride + static_cast<std::size_t>(k)];
  }
}

void solve_row_dp_u16(const KernelSet& ks, const std::uint16_t* cost_q4, std::size_t stride,
                      const std::int32_t* xs, int n, int num_disp,
                      const std::uint32_t* penalty_by_gap, std::uint16_t* f_rows,
                      std::int32_t* k_out) {
  const int d = num_disp;
  const std::uint16_t* prev = cost_q4;  // F_1 = Ca_1
  for (int i = 1; i < n; ++i) {
    std::uint16_t* cur = f_rows + i * stride;
    ks.dp_step_u16(cost_q4 + i * stride, prev, penalty_by_gap[xs[i] - xs[i - 1]], d, cur);
    prev = cur;
  }
  int k = 0;
  for (int j = 1; j < d; ++j)
    if (prev[j] < prev[k]) k = j;
  k_out[n - 1] = k;
  // Only the pointer on the path is needed: one O(D) search per sample instead
  // of n x D pointers written in the forward pass.
  for (int i = n - 1; i > 0; --i) {
    const std::uint16_t* f_before = i == 1 ? cost_q4 : f_rows + (i - 1) * stride;
    k = ks.dp_pointer_u16(f_before, penalty_by_gap[xs[i] - xs[i - 1]], d, k);
    k_out[i - 1] = k;
  }
}

void RowMatcher::match_row(const MatchContext& ctx, int y, const std::int32_t* xs, int n,
                           std::int16_t* disp_q4_out, RowTimes* times) {
  if (num_disp_ == 0)
    throw Error(ErrorCode::kNotConfigured, "RowMatcher::match_row before configure()");
  const StereoParams& cp = ctx.params();
  if (cp.num_disp != num_disp_ || cp.d_min != params_.d_min ||
      cp.dp.lambda_q4 != params_.dp.lambda_q4 || cp.dp.gap != params_.dp.gap ||
      cp.dp.subpixel != params_.dp.subpixel || cp.dp.subpixel_fit != params_.dp.subpixel_fit ||
      ctx.width() > max_samples_)
    throw Error(ErrorCode::kInvalidArgument,
                "RowMatcher::match_row: the MatchContext's parameters or frame width (" +
                    std::to_string(ctx.width()) + ") differ from the matcher's configuration (max width " +
                    std::to_string(max_samples_) + ")");
  const int w = ctx.width();
  if (y < 0 || y >= ctx.height())
    throw Error(ErrorCode::kInvalidArgument, "row y = " + std::to_string(y) +
                                                 " is outside 0.." + std::to_string(ctx.height() - 1));
  if (n < 0 || n > w)
    throw Error(ErrorCode::kInvalidArgument, "sample count n = " + std::to_string(n) +
                                                 " is outside 0.." + std::to_string(w));
  if (n == 0) return;
  if (xs == nullptr || disp_q4_out == nullptr)
    throw Error(ErrorCode::kInvalidArgument, "match_row: null sample or output buffer");
  for (int i = 0; i < n; ++i) {
    const int lo = i == 0 ? 0 : xs[i - 1] + 1;
    if (xs[i] < lo || xs[i] >= w)
      throw Error(ErrorCode::kInvalidArgument,
                  "sample x[" + std::to_string(i) + "] = " + std::to_string(xs[i]) +
                      (xs[i] >= w ? " is not below the width " + std::to_string(w)
                                  : " is not above the previous sample / 0"));
  }

  const int d = num_disp_;

  // Costs at every sample first (kept for the sub-pixel step anyway), so the
  // two stages can be timed with three clock reads per row.
  const std::int64_t t0 = times ? monotonic_ns() : 0;
  for (int i = 0; i < n; ++i) ctx.aggregate_sample(xs[i], y, costs_.data() + i * cost_stride_, scratch_);
  const std::int64_t t1 = times ? monotonic_ns() : 0;

  if (u16_path_)
    solve_row_dp_u16(ctx.kernels(), costs_.data(), cost_stride_, xs, n, d, penalty_.data(),
                     f_rows_.data(), index_.data());
  else
    solve_row_dp(ctx.kernels(), costs_.data(), cost_stride_, xs, n, d, penalty_.data(),
                 f_prev_.data(), f_cur_.data(), ptr_.data(), index_.data());

  const bool subpixel = params_.dp.subpixel;
  const int d_min = ctx.d_min();
  for (int i = 0; i < n; ++i) {
    const int ki = index_[static_cast<std::size_t>(i)];
    int off = 0;
    if (subpixel && ki > 0 && ki < d - 1) {
      const std::uint16_t* c = sample_costs_q4(i);
      off = subpixel_offset_q4(params_.dp.subpixel_fit, c[ki - 1], c[ki], c[ki + 1]);
    }
    disp_q4_out[i] = static_cast<std::int16_t>(kDispOne * (d_min + ki) + off);
  }
  if (times) {
    const std::int64_t t2 = monotonic_ns();
    times->cost_ns += t1 - t0;
    times->dp_ns += t2 - t1;
  }
}

}  // namespace tristereo
