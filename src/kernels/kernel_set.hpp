// The hot loops of the integer path, as a table of function pointers.
//
// Each entry has one scalar implementation (the readable reference, in the
// stage's *_scalar.cpp) and SIMD twins with the identical signature in simd/.
// simd/dispatch.cpp fills a KernelSet once per Pipeline::configure; nothing in
// a row loop ever checks the CPU. Kernels never allocate, throw or validate:
// the bounds quoted on each one are enforced by validate_params/configure.
#pragma once

#include <cstddef>
#include <climits>
#include <cstdint>

namespace tristereo {

// Largest penalty for which the u16 DP holds every F value:
// 4080 + 255 * 241 = 65535. Rows whose penalties are all <= this (lambda_q4 <=
// 241, since P(g) <= lambda) run dp_step_u16 / dp_pointer_u16 instead of dp_step.
constexpr std::uint32_t kMaxDpPenaltyU16 = 241;

// A grid point of the midpoint interpolation whose value is not known yet
// (src/interp/interpolate_midpoints.cpp): below every value it can hold,
// |16 d 2^F| < 2^27, and four equal bytes, so that a buffer of them is a
// memset (a loop of 16-byte stores, the compiler's std::fill, took 9 % of
// the interpolation).
constexpr std::int32_t kMidpointUnknownByte = 0x80;
constexpr std::int32_t kMidpointUnknown = -0x7F7F7F80;  // 0x80808080
static_assert(static_cast<std::uint32_t>(kMidpointUnknown) == 0x80808080u, "four bytes kMidpointUnknownByte");
static_assert(kMidpointUnknown < -(1 << 27), "below every value");

struct KernelSet {
  const char* name = "scalar";

  // acc[k] += min(|left - right_rev[k]|, trunc) for k in [0, n).
  // Box aggregation. Bound: window pixels * trunc <= 65535 (checked by the
  // pipeline before it picks this u16 kernel), so acc never wraps.
  void (*accumulate_abs_diff_u16)(const std::uint8_t* right_rev, std::uint8_t left,
                                  std::uint8_t trunc, int n, std::uint16_t* acc) = nullptr;

  // acc[k] += weight * min(|left - right_rev[k]|, trunc) for k in [0, n).
  // Adaptive weights (weight <= 255) or large box windows (weight = 1).
  // Bound: sum of weights * 255 < 2^26 for a 31x31 window.
  void (*accumulate_abs_diff_weighted_u32)(const std::uint8_t* right_rev, std::uint8_t left,
                                           std::uint16_t weight, std::uint8_t trunc, int n,
                                           std::uint32_t* acc) = nullptr;

  // Whole support window of one sample in one call (the stage's hot path: the
  // D sums stay in registers while the window is walked, instead of one
  // load + store of every accumulator per window pixel):
  //   sum[k] = sum_{i < count} min(|left[i] - right_rev[i][k]|, trunc), k in [0, n).
  // right_rev[i] is the reversed right run of window pixel i (as for
  // accumulate_abs_diff_u16), left[i] its left intensity; sum is overwritten.
  // Bound: count * trunc <= 65535 (the pipeline's u16 box condition); beyond
  // it both scalar and SIMD wrap mod 2^16 alike.
  void (*aggregate_window_box_u16)(const std::uint8_t* const* right_rev,
                                   const std::uint8_t* left, int count, std::uint8_t trunc,
                                   int n, std::uint16_t* sum) = nullptr;

  // Same with per-pixel weights: sum[k] = sum_i weight[i] * min(|left[i] -
  // right_rev[i][k]|, trunc). Model weights are 0..255 (SIMD twins take any
  // u16 weight; above 257 they fall back to scalar). Bound: sum of weights *
  // trunc < 2^32 (the model's < 961 * 255 * 255 < 2^26).
  void (*aggregate_window_weighted_u32)(const std::uint8_t* const* right_rev,
                                        const std::uint8_t* left, const std::uint16_t* weight,
                                        int count, std::uint8_t trunc, int n,
                                        std::uint32_t* sum) = nullptr;

  // cost_q4[k] = (sum[k] * inv_q32 * 16 + 2^31) >> 32 (docs/model.md section 2),
  // inv_q32 = floor(2^32 / sum_of_weights). Result in 0 .. 4080.
  void (*normalize_costs_u16)(const std::uint16_t* sum, std::uint64_t inv_q32, int n,
                              std::uint16_t* cost_q4) = nullptr;
  void (*normalize_costs_u32)(const std::uint32_t* sum, std::uint64_t inv_q32, int n,
                              std::uint16_t* cost_q4) = nullptr;

  // One DP step (docs/model.md section 3) over n = D disparities:
  //   g[k] = min_j prev[j] + penalty * |k - j|, ptr[k] = smallest minimising j,
  //   out[k] = cost_q4[k] + g[k] - min_k g[k].
  // Bound: prev[k] <= 4080 + 255 * penalty and penalty <= 32000, so
  // value + 255 * penalty < 2^24 and (value << 8 | j) fits 32 bits.
  void (*dp_step)(const std::uint16_t* cost_q4, const std::uint32_t* prev,
                  std::uint32_t penalty, int n, std::uint32_t* out,
                  std::uint8_t* ptr) = nullptr;

  // dp_step on u16 values without back-pointers (the row keeps every F row
  // instead and recomputes one pointer per sample with dp_pointer_u16):
  //   g[k] = min_j prev[j] + penalty * |k - j|, out[k] = cost_q4[k] + g[k] - min_k g[k]
  // (mod 2^16). Exact for any prev and penalty; out fits u16 (no wrap) when
  // prev[k] <= 4080 + 255 * penalty and penalty <= kMaxDpPenaltyU16.
  void (*dp_step_u16)(const std::uint16_t* cost_q4, const std::uint16_t* prev,
                      std::uint32_t penalty, int n, std::uint16_t* out) = nullptr;

  // Back-pointer of disparity k (0 <= k < n): the smallest j in [0, n)
  // minimising prev[j] + penalty * |k - j| (exact for any u16 prev, penalty).
  int (*dp_pointer_u16)(const std::uint16_t* prev, std::uint32_t penalty, int n, int k) = nullptr;

  // Census transform of one row (docs/model.md section 2): bit b of pixel x's
  // descriptor is 1 when the b-th neighbour of its win_w x win_h window (raster
  // order, centre skipped) is below the centre; bits 8p .. 8p + 7 go to
  // planes[p][x], p < ceil((win_w win_h - 1) / 8). rows[j], j < win_h, point at
  // x = 0 of the window's rows, readable from -win_w/2 to width - 1 + win_w/2
  // (the caller replicates the border). width >= 1.
  void (*census_row_u8)(const std::uint8_t* const* rows, int win_w, int win_h, int width,
                        std::uint8_t* const* planes) = nullptr;

  // Hamming cost over a support window, one descriptor byte plane per entry:
  //   sum[k] = sum_{i < count} popcount(left[i] ^ right_rev[i][k]), k in [0, n).
  // Bound: count * 8 <= 65535 (31 x 31 window x 8 planes = 7688 entries).
  // right_rev[i] may be read up to 64 elements past n (the rows' slack).
  void (*census_window_u16)(const std::uint8_t* const* right_rev, const std::uint8_t* left,
                            int count, int n, std::uint16_t* sum) = nullptr;

  // Per-pixel Hamming costs of a whole row (the census cost's first step, one
  // call per row instead of one census_window_u16 per pixel):
  //   out[x * stride + k] = sum_{p < planes} popcount(left[p][x] ^ right_rev[p][k - x])
  // for x in [0, width), k in [0, n): right_rev[p] is pixel 0's reversed run,
  // pixel x's starts x elements before it. 1 <= planes <= 8, stride >= n; the
  // runs may be read up to 64 elements past n.
  void (*census_costs_row_u16)(const std::uint8_t* const* right_rev, const std::uint8_t* const* left,
                               int planes, int width, int n, std::size_t stride,
                               std::uint16_t* out) = nullptr;

  // census_costs_row_u16 with one byte per cost (at most 64 bits differ).
  void (*census_costs_row_u8)(const std::uint8_t* const* right_rev, const std::uint8_t* const* left,
                              int planes, int width, int n, std::size_t stride, std::uint8_t* out) = nullptr;

  // sum[j] = sum_{i < count} rows[i][j] (mod 2^16), j in [0, n): the census
  // cost's box sums, over a window's rows and then its columns. count >= 1.
  void (*sum_rows_u16)(const std::uint16_t* const* rows, int count, std::size_t n,
                       std::uint16_t* sum) = nullptr;
  // The same on bytes (mod 2^8): the box sums of a census whose window sum
  // cannot exceed 255 (descriptor bits x window pixels <= 255), half the bytes.
  void (*sum_rows_u8)(const std::uint8_t* const* rows, int count, std::size_t n,
                      std::uint8_t* sum) = nullptr;
  // normalize_costs_u16 of byte sums.
  void (*normalize_costs_u8)(const std::uint8_t* sum, std::uint64_t inv_q32, int n,
                             std::uint16_t* cost_q4) = nullptr;

  // The steps of `count` paths at one sample (docs/model.md section 3b),
  // 1 <= count <= 4, sharing its cost row and its sum. For each path r < count
  // and k in [0, n):
  //   out[r][k] = cost[k] + min(prev[r][k], prev[r][k-1] + p1[r], prev[r][k+1] + p1[r],
  //                             prev_min[r] + p2[r]) - prev_min[r]
  // with prev[r][-1] = prev[r][n] = 0xFFFF guards read by the kernel (the
  // sums saturate), mins[r] = min_k out[r][k], and
  //   sum[k] = (accumulate ? sum[k] : 0) + sum_r out[r][k]   (mod 2^16),
  // the same as one path at a time, the first added with `accumulate` and the
  // others with 1 (path_step_u16_scalar), for one load of C and one
  // read-modify-write of S per sample instead of one per path. Bounds
  // (validate_params): prev[r][k] <= max cost + p2[r], prev_min[r] + p2[r] <=
  // 65535, sums <= 65535. cost and prev[r] may be read up to 64 elements past
  // n; out[r] is none of the prev rows, cost or sum.
  void (*path_steps_u16)(const std::uint16_t* cost, const std::uint16_t* const* prev,
                         const std::uint16_t* prev_min, const std::uint16_t* p1, const std::uint16_t* p2,
                         int count, int n, std::uint16_t* const* out, std::uint16_t* sum, int accumulate,
                         std::uint16_t* mins) = nullptr;

  // path_steps_u16 on census box sums kept as bytes, for k in [0, n):
  //   cost[k] = (16 cost_sums[k] inv_q15 + 2^14) >> 15,  inv_q15 <= 32767,
  // computed in registers (the Q4 costs are never stored). This equals the
  // model's mean of a box of p pixels (normalize_costs_u8 with floor(2^32 /
  // p)) only for an inv_q15 checked against it for every sum the box can hold
  // (src/cost/byte_means.hpp chooses them). Reads cost_sums[0 .. n); n <= 256.
  void (*path_steps_u8)(const std::uint8_t* cost_sums, std::uint16_t inv_q15, const std::uint16_t* const* prev,
                        const std::uint16_t* prev_min, const std::uint16_t* p1, const std::uint16_t* p2, int count,
                        int n, std::uint16_t* const* out, std::uint16_t* sum, int accumulate,
                        std::uint16_t* mins) = nullptr;

  // One sample's decision inputs from its summed costs (docs/model.md
  // section 6), for k in [0, n), 1 <= n <= 256: returns the smallest k
  // minimising total[k]; when rival is given, *rival = the minimum of
  // total[j] over |j - k| > 1, or 0xFFFF when there is none (the uniqueness
  // test's rival); when best_cost is given, the right view's running winner
  // along the row (left-right check from the summed costs):
  //   if (total[k] < best_cost[k]) { best_cost[k] = total[k]; best_k[k] = k; }
  // The caller offers a row's samples left to right, so of equal costs the
  // smallest k (the one offered first) stays; best_cost starts at 0xFFFF,
  // above every summed cost (validate_params keeps them <= 65534).
  int (*winner_u16)(const std::uint16_t* total, int n, std::uint16_t* rival, std::uint16_t* best_cost,
                    std::uint16_t* best_k) = nullptr;

  // The minimum of total[j] over |j - k| > 1, 0 <= k < n, or 0xFFFF when
  // there is none (winner_u16's rival, for a k found otherwise: the support
  // prior's data rival at its new winner).
  std::uint16_t (*min_outside_u16)(const std::uint16_t* total, int n, int k) = nullptr;

  // The support prior's costs (docs/model.md section 6b), n >= 1:
  //   out[k] = min(total[k] + penalty[k], 65535).
  // penalty is the prior's table shifted to the sample's k_prior; a sum that
  // saturates is above every S'(k') (<= 65534), so winner_u16 on out finds
  // the exact winner, and its rival whenever that is below 65535.
  void (*add_saturate_u16)(const std::uint16_t* total, const std::uint16_t* penalty, int n,
                           std::uint16_t* out) = nullptr;

  // The tritree's side-4 level (src/tritree/side4_shapes.hpp, docs/tritree.md)
  // for n >= 1 squares of 4 x 4 pixels side by side: square m's pixel (dx, dy)
  // is rows[dy][4 m + dx] (dy <= 4: row 4 and column 4 n hold the lower and
  // right corners; nothing else is read), diagonals alternating along the
  // row, '\' first when first_backslash. Per square:
  //   wants[m] bit k (k < 4): side triangle k's SSE > sse_limit[k]; bit 4 + p:
  //     half p's SSE > sse_limit[4 + 2 d + p] (d = 0 '\', 1 '/');
  //   sums[c * sums_stride + m], c = 4 p + j: half p's sum over its pixels of
  //     I, dx I, dy I, I^2 (j = 0..3), relative to the square's corner.
  // SSE is the exact squared plane residual, < 2^27 (side4_shapes.hpp), so any
  // int32 limit works (INT32_MAX: never).
  void (*side4_tests_u8)(const std::uint8_t* const* rows, int n, int first_backslash,
                         const std::int32_t* sse_limit, std::uint32_t* wants, std::int32_t* sums,
                         std::size_t sums_stride) = nullptr;

  // The tritree's side-8 level (src/tritree/side8_shapes.hpp) for n >= 1
  // squares of 8 x 8 pixels side by side, from side4_tests_u8's output for
  // the two rows of 4 x 4 squares they cover: quad_sums[dy] (dy = 0, 1) its
  // sums planes (plane c at quad_sums[dy] + c * quad_stride, 4 x 4 square
  // 2 i + dx under square i); the corners are rows[0][8 i], rows[0][8 i + 8],
  // rows[2][8 i], rows[2][8 i + 8] and the centre rows[1][8 i + 4] (rows 0, 4
  // and 8 of the row of squares). Diagonals alternate along the row, '\'
  // first when first_backslash. Per square, as side4_tests_u8: wants[i] bit
  // k: side triangle k's SSE > sse_limit[k], bit 4 + p: half p's SSE >
  // sse_limit[4 + 2 d + p]; sums[c * sums_stride + i], c = 4 p + j: half p's
  // I, xI, yI, II relative to the square's corner. SSE < 2^37, exact.
  void (*side8_tests_s32)(const std::int32_t* const* quad_sums, std::size_t quad_stride,
                          const std::uint8_t* const* rows, int n, int first_backslash,
                          const std::int64_t* sse_limit, std::uint32_t* wants, std::int32_t* sums,
                          std::size_t sums_stride) = nullptr;

  // The midpoint interpolation's side-2 level on one grid row, rounded to Q4
  // (src/interp/interpolate_midpoints.hpp): for x in [0, n), v = row[x] when
  // it is known, else the average (a + b) >> 1 of the two points whose
  // midpoint it is:
  //   even row (above == below == nullptr): a, b = row[x - 1], row[x + 1];
  //   odd row, even x: above[x], below[x];
  //   odd row, odd x: the 2 x 2 square's diagonal, '\' (above[x - 1],
  //     below[x + 1]) when (x >> 1) is even and first_backslash, or odd and
  //     not, else '/' (above[x + 1], below[x - 1]);
  // then disp_q4[x] = (v + 2^(frac_bits - 1)) >> frac_bits. row, above and
  // below are read from index -1 to n. Precondition (the caller's levels
  // above side 2): every point an unknown one averages is known; the others'
  // averages are computed and discarded, mod 2^32. 1 <= frac_bits <= 11.
  void (*midpoints_row_q4)(const std::int32_t* above, const std::int32_t* row, const std::int32_t* below,
                           int n, int first_backslash, int frac_bits, std::int16_t* disp_q4) = nullptr;

  // midpoints_row_q4 and, in the same pass, the pixel confidence and state
  // (docs/model.md section 7): conf_above, conf_row and conf_below hold the
  // confidences (0..255) of the points of above, row and below, index for
  // index (conf_above and conf_below null with above and below). A known
  // point keeps its own; an unknown one takes the smaller of the two points'
  // it averages. Then confidence[x] = that value and state[x] = 0 when it is
  // 0, 1 below 128, else 2. Same reads (index -1 to n) and precondition as
  // midpoints_row_q4.
  void (*midpoints_row_conf_q4)(const std::int32_t* above, const std::int32_t* row, const std::int32_t* below,
                                const std::uint8_t* conf_above, const std::uint8_t* conf_row,
                                const std::uint8_t* conf_below, int n, int first_backslash, int frac_bits,
                                std::int16_t* disp_q4, std::uint8_t* confidence, std::uint8_t* state) = nullptr;

  // One row of colour to gray (docs/model.md section 0, include/tristereo/gray.hpp):
  // gray[x] = (77 R + 150 G + 29 B + 128) >> 8 for the RGB triplet x, x in [0, n).
  void (*rgb_to_gray_row_u8)(const std::uint8_t* rgb, int n, std::uint8_t* gray) = nullptr;
  // The same for BGR triplets (the Python module's order='bgr').
  void (*bgr_to_gray_row_u8)(const std::uint8_t* bgr, int n, std::uint8_t* gray) = nullptr;

  // One row of the rectification's bilinear remap (include/tristereo/rectify.hpp),
  // for i in [0, n): with ix, iy = xy[2 i], xy[2 i + 1], fx = frac[i] & 31,
  // fy = frac[i] >> 5 and s = src + iy * stride + ix,
  //   out[i] = (s[0] (32 - fx)(32 - fy) + s[1] fx (32 - fy)
  //             + s[stride] (32 - fx) fy + s[stride + 1] fx fy + 512) >> 10.
  // All four taps must be readable (the map keeps other pixels out of the
  // rows). The sum is < 255 * 1024 + 512 < 2^18: int32 never overflows.
  void (*remap_bilinear_row_u8)(const std::uint8_t* src, std::size_t stride, const std::int16_t* xy,
                                const std::uint16_t* frac, int n, std::uint8_t* out) = nullptr;
};

// The portable reference set (always available).
const KernelSet& scalar_kernel_set();

}  // namespace tristereo
