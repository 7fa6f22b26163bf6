// Scalar kernels: the readable reference for every entry of KernelSet.
// SIMD twins in simd/ have the same signatures and must produce identical output.
#pragma once

#include <cstddef>
#include <cstdint>

namespace tristereo {

void accumulate_abs_diff_u16_scalar(const std::uint8_t* right_rev, std::uint8_t left,
                                    std::uint8_t trunc, int n, std::uint16_t* acc);
void accumulate_abs_diff_weighted_u32_scalar(const std::uint8_t* right_rev, std::uint8_t left,
                                             std::uint16_t weight, std::uint8_t trunc, int n,
                                             std::uint32_t* acc);
// Loops over the window pixels calling the per-pixel kernels above: the
// definition the fused SIMD window kernels are checked against.
void aggregate_window_box_u16_scalar(const std::uint8_t* const* right_rev,
                                     const std::uint8_t* left, int count, std::uint8_t trunc,
                                     int n, std::uint16_t* sum);
void aggregate_window_weighted_u32_scalar(const std::uint8_t* const* right_rev,
                                          const std::uint8_t* left, const std::uint16_t* weight,
                                          int count, std::uint8_t trunc, int n,
                                          std::uint32_t* sum);
void normalize_costs_u16_scalar(const std::uint16_t* sum, std::uint64_t inv_q32, int n,
                                std::uint16_t* cost_q4);
void normalize_costs_u8_scalar(const std::uint8_t* sum, std::uint64_t inv_q32, int n, std::uint16_t* cost_q4);
void normalize_costs_u32_scalar(const std::uint32_t* sum, std::uint64_t inv_q32, int n,
                                std::uint16_t* cost_q4);
void dp_step_scalar(const std::uint16_t* cost_q4, const std::uint32_t* prev,
                    std::uint32_t penalty, int n, std::uint32_t* out, std::uint8_t* ptr);

void dp_step_u16_scalar(const std::uint16_t* cost_q4, const std::uint16_t* prev,
                        std::uint32_t penalty, int n, std::uint16_t* out);
int dp_pointer_u16_scalar(const std::uint16_t* prev, std::uint32_t penalty, int n, int k);

int census_popcount_u8(std::uint8_t v);
void census_row_u8_scalar(const std::uint8_t* const* rows, int win_w, int win_h, int width,
                           std::uint8_t* const* planes);
void census_window_u16_scalar(const std::uint8_t* const* right_rev, const std::uint8_t* left,
                              int count, int n, std::uint16_t* sum);
void census_costs_row_u16_scalar(const std::uint8_t* const* right_rev, const std::uint8_t* const* left,
                                 int planes, int width, int n, std::size_t stride, std::uint16_t* out);
void census_costs_row_u8_scalar(const std::uint8_t* const* right_rev, const std::uint8_t* const* left,
                                int planes, int width, int n, std::size_t stride, std::uint8_t* out);
void sum_rows_u16_scalar(const std::uint16_t* const* rows, int count, std::size_t n, std::uint16_t* sum);
void sum_rows_u8_scalar(const std::uint8_t* const* rows, int count, std::size_t n, std::uint8_t* sum);
// One path of path_steps_u16 (returns its minimum; sum gets out added when
// accumulate, else out).
std::uint16_t path_step_u16_scalar(const std::uint16_t* cost, const std::uint16_t* prev,
                                   std::uint16_t prev_min, std::uint16_t p1, std::uint16_t p2,
                                   int n, std::uint16_t* out, std::uint16_t* sum,
                                   int accumulate);
void path_steps_u16_scalar(const std::uint16_t* cost, const std::uint16_t* const* prev,
                           const std::uint16_t* prev_min, const std::uint16_t* p1, const std::uint16_t* p2,
                           int count, int n, std::uint16_t* const* out, std::uint16_t* sum, int accumulate,
                           std::uint16_t* mins);
void path_steps_u8_scalar(const std::uint8_t* cost_sums, std::uint16_t inv_q15, const std::uint16_t* const* prev,
                          const std::uint16_t* prev_min, const std::uint16_t* p1, const std::uint16_t* p2, int count,
                          int n, std::uint16_t* const* out, std::uint16_t* sum, int accumulate, std::uint16_t* mins);
std::uint16_t min_outside_u16_scalar(const std::uint16_t* total, int n, int k);
void lr_min_u16_scalar(const std::uint16_t* total, int n, std::uint16_t* best_cost,
                       std::uint16_t* best_k);
int winner_u16_scalar(const std::uint16_t* total, int n, std::uint16_t* rival, std::uint16_t* best_cost,
                      std::uint16_t* best_k);
// In src/select/prior_kernels_scalar.cpp.
void add_saturate_u16_scalar(const std::uint16_t* total, const std::uint16_t* penalty, int n,
                             std::uint16_t* out);
// In src/tritree/side4_tests_scalar.cpp.
void side4_tests_u8_scalar(const std::uint8_t* const* rows, int n, int first_backslash,
                           const std::int32_t* sse_limit, std::uint32_t* wants, std::int32_t* sums,
                           std::size_t sums_stride);
// In src/tritree/side8_tests_scalar.cpp.
void side8_tests_s32_scalar(const std::int32_t* const* quad_sums, std::size_t quad_stride,
                            const std::uint8_t* const* rows, int n, int first_backslash,
                            const std::int64_t* sse_limit, std::uint32_t* wants, std::int32_t* sums,
                            std::size_t sums_stride);
// In src/rectify/remap_scalar.cpp.
void remap_bilinear_row_u8_scalar(const std::uint8_t* src, std::size_t stride, const std::int16_t* xy,
                                  const std::uint16_t* frac, int n, std::uint8_t* out);
// In src/interp/midpoints_row_scalar.cpp.
void midpoints_row_q4_scalar(const std::int32_t* above, const std::int32_t* row, const std::int32_t* below, int n,
                             int first_backslash, int frac_bits, std::int16_t* disp_q4);
void midpoints_row_conf_q4_scalar(const std::int32_t* above, const std::int32_t* row, const std::int32_t* below,
                                  const std::uint8_t* conf_above, const std::uint8_t* conf_row,
                                  const std::uint8_t* conf_below, int n, int first_backslash, int frac_bits,
                                  std::int16_t* disp_q4, std::uint8_t* confidence, std::uint8_t* state);

}  // namespace tristereo
