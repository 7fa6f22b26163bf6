#include "src/kernels/kernel_set.hpp"
#include "src/kernels/kernels_scalar.hpp"
#include "tristereo/gray.hpp"

namespace tristereo {

const KernelSet& scalar_kernel_set() {
  static const KernelSet set = [] {
    KernelSet s;
    s.name = "scalar";
    s.accumulate_abs_diff_u16 = accumulate_abs_diff_u16_scalar;
    s.accumulate_abs_diff_weighted_u32 = accumulate_abs_diff_weighted_u32_scalar;
    s.aggregate_window_box_u16 = aggregate_window_box_u16_scalar;
    s.aggregate_window_weighted_u32 = aggregate_window_weighted_u32_scalar;
    s.normalize_costs_u16 = normalize_costs_u16_scalar;
    s.normalize_costs_u32 = normalize_costs_u32_scalar;
    s.dp_step = dp_step_scalar;
    s.dp_step_u16 = dp_step_u16_scalar;
    s.dp_pointer_u16 = dp_pointer_u16_scalar;
    s.census_row_u8 = census_row_u8_scalar;
    s.census_window_u16 = census_window_u16_scalar;
    s.census_costs_row_u16 = census_costs_row_u16_scalar;
    s.census_costs_row_u8 = census_costs_row_u8_scalar;
    s.sum_rows_u8 = sum_rows_u8_scalar;
    s.normalize_costs_u8 = normalize_costs_u8_scalar;
    s.path_steps_u16 = path_steps_u16_scalar;
    s.path_steps_u8 = path_steps_u8_scalar;
    s.sum_rows_u16 = sum_rows_u16_scalar;
    s.winner_u16 = winner_u16_scalar;
    s.min_outside_u16 = min_outside_u16_scalar;
    s.add_saturate_u16 = add_saturate_u16_scalar;
    s.rgb_to_gray_row_u8 = rgb_to_gray_row_scalar;
    s.bgr_to_gray_row_u8 = bgr_to_gray_row_scalar;
    s.side4_tests_u8 = side4_tests_u8_scalar;
    s.side8_tests_s32 = side8_tests_s32_scalar;
    s.midpoints_row_q4 = midpoints_row_q4_scalar;
    s.remap_bilinear_row_u8 = remap_bilinear_row_u8_scalar;
    s.midpoints_row_conf_q4 = midpoints_row_conf_q4_scalar;
    return s;
  }();
  return set;
}

}  // namespace tristereo
