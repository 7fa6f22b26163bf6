// Reference: the per-row DP and sub-pixel refinement (docs/model.md section 3),
// by the O(D^2) recurrence: an independent check of the O(D) min-convolution.
#include <cmath>
#include <cstdlib>
#include <string>

#include "src/reference/ref_match.hpp"
#include "tristereo/status.hpp"

namespace tristereo {
namespace reference {

std::int64_t gap_penalty(const DpParams& dp, int gap) {
  const double lambda = dp.lambda_q4, g = gap;
  double tau_num = 1, tau_den = 1;  // tau(g) = tau_num / tau_den
  switch (dp.gap) {
    case GapPolicy::kInvSquare: tau_den = g * g; break;
    case GapPolicy::kInverse: tau_den = g; break;
    case GapPolicy::kConstant: break;
  }
  // round(lambda tau) halves up = floor((2 lambda + den) / (2 den)) with exact
  // integers (< 2^26); floor of the double quotient is exact because a
  // non-integer quotient is at least 1/(2 den) >= 2^-26 from any integer.
  return static_cast<std::int64_t>(std::floor((2 * lambda * tau_num + tau_den) / (2 * tau_den)));
}

void dp_step_brute_force(const std::vector<std::int64_t>& cost,
                         const std::vector<std::int64_t>& prev, std::int64_t penalty,
                         std::vector<std::int64_t>& out, std::vector<int>& ptr) {
  const int n = static_cast<int>(cost.size());
  std::vector<std::int64_t> g(static_cast<std::size_t>(n));
  ptr.assign(static_cast<std::size_t>(n), 0);
  for (int k = 0; k < n; ++k) {
    std::int64_t best = prev[0] + penalty * k;
    int best_j = 0;
    for (int j = 1; j < n; ++j) {
      const std::int64_t v = prev[static_cast<std::size_t>(j)] + penalty * std::abs(k - j);
      if (v < best) {  // strict: ties keep the smaller j
        best = v;
        best_j = j;
      }
    }
    g[static_cast<std::size_t>(k)] = best;
    ptr[static_cast<std::size_t>(k)] = best_j;
  }
  std::int64_t min_g = g[0];
  for (std::int64_t v : g) min_g = std::min(min_g, v);
  out.resize(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k)
    out[static_cast<std::size_t>(k)] =
        cost[static_cast<std::size_t>(k)] + g[static_cast<std::size_t>(k)] - min_g;
}

std::vector<int> dp_solve(const std::vector<std::vector<std::int64_t>>& cost,
                          const std::vector<std::int64_t>& penalty) {
  const std::size_t n = cost.size();
  if (n == 0) return {};
  std::vector<std::int64_t> f = cost[0], next;
  std::vector<std::vector<int>> ptr(n);
  for (std::size_t i = 1; i < n; ++i) {
    dp_step_brute_force(cost[i], f, penalty[i], next, ptr[i]);
    f = next;
  }
  int k = 0;
  for (int j = 1; j < static_cast<int>(f.size()); ++j)
    if (f[static_cast<std::size_t>(j)] < f[static_cast<std::size_t>(k)]) k = j;
  std::vector<int> ks(n);
  for (std::size_t i = n; i-- > 0;) {
    ks[i] = k;
    if (i > 0) k = ptr[i][static_cast<std::size_t>(k)];
  }
  return ks;
}

int subpixel_offset_q4(int cm, int c0, int cp) {
  const int den = cm + cp - 2 * c0;
  if (den <= 0) return 0;
  // q = 16 (cm - cp) / (2 den), |q| < 2^20, den <= 131068 (the paths' summed
  // costs; 8160 for the row DP's). floor(q + 0.5) in double equals the model's
  // floor((16 (cm - cp) + den) / (2 den)): if the true q is a half-integer it
  // is exactly representable, so q and q + 0.5 are computed exactly; otherwise
  // q is at least 1/(4 den) > 2^-19 away from every half-integer, far more than
  // the rounding error (< 2^-31) of the division and the addition, so the floor
  // cannot flip.
  const double q = 16.0 * (cm - cp) / (2.0 * den);
  const double off = std::floor(q + 0.5);
  return static_cast<int>(std::min(8.0, std::max(-8.0, off)));
}

int equiangular_offset_q4(int cm, int c0, int cp) {
  // The symmetric V through the three costs: slopes +m and -m with
  // m = max(cm, cp) - c0; its vertex lies (cm - cp) / (2 m) px from k. The
  // argument of subpixel_offset_q4 holds with m in place of den (m <= 65534, so
  // a q that is not a half-integer is at least 2^-19 from one).
  const int m = std::max(cm, cp) - c0;
  if (m <= 0) return 0;
  const double q = 16.0 * (cm - cp) / (2.0 * m);
  const double off = std::floor(q + 0.5);
  return static_cast<int>(std::min(8.0, std::max(-8.0, off)));
}

int subpixel_offset_q4(const DpParams& dp, int cm, int c0, int cp) {
  return dp.subpixel_fit == SubpixelFit::kEquiangular ? equiangular_offset_q4(cm, c0, cp)
                                                       : subpixel_offset_q4(cm, c0, cp);
}

std::vector<std::int16_t> match_row(const ImageU8& left, const ImageU8& right, int y,
                                    const std::vector<int>& xs, const StereoParams& params) {
  for (std::size_t i = 1; i < xs.size(); ++i)
    if (xs[i] <= xs[i - 1])
      throw Error(ErrorCode::kInvalidArgument,
                  "samples must increase: x[" + std::to_string(i) + "] = " + std::to_string(xs[i]));
  const std::vector<std::vector<int>> ca = aggregated_costs(left, right, y, xs, params);
  std::vector<std::vector<std::int64_t>> cost(ca.size());
  std::vector<std::int64_t> penalty(ca.size(), 0);
  for (std::size_t i = 0; i < ca.size(); ++i) {
    cost[i].assign(ca[i].begin(), ca[i].end());
    if (i > 0) penalty[i] = gap_penalty(params.dp, xs[i] - xs[i - 1]);
  }
  const std::vector<int> ks = dp_solve(cost, penalty);
  std::vector<std::int16_t> disp(xs.size());
  for (std::size_t i = 0; i < xs.size(); ++i) {
    const int k = ks[i];
    int off = 0;
    if (params.dp.subpixel && k > 0 && k < params.num_disp - 1)
      off = subpixel_offset_q4(params.dp, ca[i][static_cast<std::size_t>(k - 1)],
                               ca[i][static_cast<std::size_t>(k)],
                               ca[i][static_cast<std::size_t>(k + 1)]);
    disp[i] = static_cast<std::int16_t>(16 * (params.d_min + k) + off);
  }
  return disp;
}

}  // namespace reference
}  // namespace tristereo
