// The avx2 instantiation of every kernel in simd/kernels-inl.hpp. This is the
// only translation unit built with the avx2 flags (see simd/CMakeLists.txt), so
// nothing here may be an inline non-template function shared with other code.
#include "simd/kernels-inl.hpp"
#include "src/kernels/kernel_set.hpp"

namespace tristereo {
namespace simd {

TRISTEREO_SIMD_KERNELS_FOR_ARCH(, xsimd::avx2)

// Fills the caller's table (no KernelSet is constructed in this TU).
void fill_kernel_set_avx2(KernelSet& set) {
  set.name = "avx2";
  set.accumulate_abs_diff_u16 = &AccumulateAbsDiffU16<xsimd::avx2>::call;
  set.accumulate_abs_diff_weighted_u32 = &AccumulateAbsDiffWeightedU32<xsimd::avx2>::call;
  set.aggregate_window_box_u16 = &AggregateWindowBoxU16<xsimd::avx2>::call;
  set.aggregate_window_weighted_u32 = &AggregateWindowWeightedU32<xsimd::avx2>::call;
  set.normalize_costs_u16 = &NormalizeCostsU16<xsimd::avx2>::call;
  set.normalize_costs_u32 = &NormalizeCostsU32<xsimd::avx2>::call;
  set.dp_step = &DpStep<xsimd::avx2>::call;
  set.dp_step_u16 = &DpStepU16<xsimd::avx2>::call;
  set.dp_pointer_u16 = &DpPointerU16<xsimd::avx2>::call;
  set.census_row_u8 = &CensusRowU8<xsimd::avx2>::call;
  set.census_window_u16 = &CensusWindowU16<xsimd::avx2>::call;
  set.census_costs_row_u16 = &CensusCostsRowU16<xsimd::avx2>::call;
  set.sum_rows_u16 = &SumRowsU16<xsimd::avx2>::call;
  set.census_costs_row_u8 = &CensusCostsRowU8<xsimd::avx2>::call;
  set.sum_rows_u8 = &SumRowsU8<xsimd::avx2>::call;
  set.normalize_costs_u8 = &NormalizeCostsU8<xsimd::avx2>::call;
  set.path_steps_u16 = &PathStepsU16<xsimd::avx2>::call;
  set.path_steps_u8 = &PathStepsU8<xsimd::avx2>::call;
  set.winner_u16 = &WinnerU16<xsimd::avx2>::call;
  set.min_outside_u16 = &MinOutsideU16<xsimd::avx2>::call;
  set.add_saturate_u16 = &AddSaturateU16<xsimd::avx2>::call;
  set.rgb_to_gray_row_u8 = &RgbToGrayRowU8<xsimd::avx2>::call;
  set.bgr_to_gray_row_u8 = &BgrToGrayRowU8<xsimd::avx2>::call;
  set.side4_tests_u8 = &Side4TestsU8<xsimd::avx2>::call;
  set.side8_tests_s32 = &Side8TestsS32<xsimd::avx2>::call;
  set.midpoints_row_q4 = &MidpointsRowQ4<xsimd::avx2>::call;
  set.remap_bilinear_row_u8 = &RemapBilinearRowU8<xsimd::avx2>::call;
  set.midpoints_row_conf_q4 = &MidpointsRowConfQ4<xsimd::avx2>::call;
}

}  // namespace simd
}  // namespace tristereo
