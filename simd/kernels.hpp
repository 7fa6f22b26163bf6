// SIMD twins of the KernelSet entries (src/kernels/kernel_set.hpp), written once
// against xsimd and instantiated per architecture in simd/arch_<arch>.cpp, the
// only files compiled with arch flags.
//
// Each kernel is a class template on the xsimd arch tag with one static entry
// point `call` whose signature is that of its scalar twin, so &K<Arch>::call
// goes straight into a KernelSet. Bodies live out of class in kernels-inl.hpp:
// an in-class body would be implicitly inline and compiled (with whatever
// flags) in every includer, which defeats the extern templates below.
// Semantics, bounds and rounding are exactly those documented in kernel_set.hpp.
#pragma once

#include <cstddef>
#include <cstdint>

#include <xsimd/xsimd.hpp>

namespace tristereo {
namespace simd {

template <class Arch>
struct AccumulateAbsDiffU16 {
  static void call(const std::uint8_t* right_rev, std::uint8_t left, std::uint8_t trunc, int n,
                   std::uint16_t* acc);
};

template <class Arch>
struct AccumulateAbsDiffWeightedU32 {
  static void call(const std::uint8_t* right_rev, std::uint8_t left, std::uint16_t weight,
                   std::uint8_t trunc, int n, std::uint32_t* acc);
};

template <class Arch>
struct AggregateWindowBoxU16 {
  static void call(const std::uint8_t* const* right_rev, const std::uint8_t* left, int count,
                   std::uint8_t trunc, int n, std::uint16_t* sum);
};

template <class Arch>
struct AggregateWindowWeightedU32 {
  static void call(const std::uint8_t* const* right_rev, const std::uint8_t* left,
                   const std::uint16_t* weight, int count, std::uint8_t trunc, int n,
                   std::uint32_t* sum);
};

template <class Arch>
struct NormalizeCostsU16 {
  static void call(const std::uint16_t* sum, std::uint64_t inv_q32, int n, std::uint16_t* cost_q4);
};

template <class Arch>
struct NormalizeCostsU32 {
  static void call(const std::uint32_t* sum, std::uint64_t inv_q32, int n, std::uint16_t* cost_q4);
};

template <class Arch>
struct DpStep {
  static void call(const std::uint16_t* cost_q4, const std::uint32_t* prev, std::uint32_t penalty,
                   int n, std::uint32_t* out, std::uint8_t* ptr);
};

template <class Arch>
struct DpStepU16 {
  static void call(const std::uint16_t* cost_q4, const std::uint16_t* prev, std::uint32_t penalty,
                   int n, std::uint16_t* out);
};

template <class Arch>
struct DpPointerU16 {
  static int call(const std::uint16_t* prev, std::uint32_t penalty, int n, int k);
};

template <class Arch>
struct CensusRowU8 {
  static void call(const std::uint8_t* const* rows, int win_w, int win_h, int width,
                   std::uint8_t* const* planes);
};

template <class Arch>
struct CensusWindowU16 {
  static void call(const std::uint8_t* const* right_rev, const std::uint8_t* left, int count,
                   int n, std::uint16_t* sum);
};

template <class Arch>
struct CensusCostsRowU16 {
  static void call(const std::uint8_t* const* right_rev, const std::uint8_t* const* left, int planes,
                   int width, int n, std::size_t stride, std::uint16_t* out);
};

template <class Arch>
struct CensusCostsRowU8 {
  static void call(const std::uint8_t* const* right_rev, const std::uint8_t* const* left, int planes,
                   int width, int n, std::size_t stride, std::uint8_t* out);
};

template <class Arch>
struct SumRowsU16 {
  static void call(const std::uint16_t* const* rows, int count, std::size_t n, std::uint16_t* sum);
};

template <class Arch>
struct SumRowsU8 {
  static void call(const std::uint8_t* const* rows, int count, std::size_t n, std::uint8_t* sum);
};

template <class Arch>
struct NormalizeCostsU8 {
  static void call(const std::uint8_t* sum, std::uint64_t inv_q32, int n, std::uint16_t* cost_q4);
};

template <class Arch>
struct PathStepsU8 {
  static void call(const std::uint8_t* cost_sums, std::uint16_t inv_q15, const std::uint16_t* const* prev,
                   const std::uint16_t* prev_min, const std::uint16_t* p1, const std::uint16_t* p2, int count, int n,
                   std::uint16_t* const* out, std::uint16_t* sum, int accumulate, std::uint16_t* mins);
};

template <class Arch>
struct PathStepsU16 {
  static void call(const std::uint16_t* cost, const std::uint16_t* const* prev, const std::uint16_t* prev_min,
                   const std::uint16_t* p1, const std::uint16_t* p2, int count, int n, std::uint16_t* const* out,
                   std::uint16_t* sum, int accumulate, std::uint16_t* mins);
};

template <class Arch>
struct WinnerU16 {
  static int call(const std::uint16_t* total, int n, std::uint16_t* rival, std::uint16_t* best_cost,
                  std::uint16_t* best_k);
};

template <class Arch>
struct MinOutsideU16 {
  static std::uint16_t call(const std::uint16_t* total, int n, int k);
};

template <class Arch>
struct AddSaturateU16 {
  static void call(const std::uint16_t* total, const std::uint16_t* penalty, int n, std::uint16_t* out);
};

template <class Arch>
struct RgbToGrayRowU8 {
  static void call(const std::uint8_t* rgb, int n, std::uint8_t* gray);
};

template <class Arch>
struct BgrToGrayRowU8 {
  static void call(const std::uint8_t* bgr, int n, std::uint8_t* gray);
};

template <class Arch>
struct Side4TestsU8 {
  static void call(const std::uint8_t* const* rows, int n, int first_backslash, const std::int32_t* sse_limit,
                   std::uint32_t* wants, std::int32_t* sums, std::size_t sums_stride);
};

template <class Arch>
struct Side8TestsS32 {
  static void call(const std::int32_t* const* quad_sums, std::size_t quad_stride, const std::uint8_t* const* rows,
                   int n, int first_backslash, const std::int64_t* sse_limit, std::uint32_t* wants,
                   std::int32_t* sums, std::size_t sums_stride);
};

template <class Arch>
struct MidpointsRowQ4 {
  static void call(const std::int32_t* above, const std::int32_t* row, const std::int32_t* below, int n,
                   int first_backslash, int frac_bits, std::int16_t* disp_q4);
};

template <class Arch>
struct RemapBilinearRowU8 {
  static void call(const std::uint8_t* src, std::size_t stride, const std::int16_t* xy, const std::uint16_t* frac,
                   int n, std::uint8_t* out);
};

template <class Arch>
struct MidpointsRowConfQ4 {
  static void call(const std::int32_t* above, const std::int32_t* row, const std::int32_t* below,
                   const std::uint8_t* conf_above, const std::uint8_t* conf_row, const std::uint8_t* conf_below,
                   int n, int first_backslash, int frac_bits, std::int16_t* disp_q4, std::uint8_t* confidence,
                   std::uint8_t* state);
};

// The instantiations live in simd/arch_<arch>.cpp; nobody else may instantiate.
#define TRISTEREO_SIMD_KERNELS_FOR_ARCH(KEYWORD, ARCH)        \
  KEYWORD template struct AccumulateAbsDiffU16<ARCH>;         \
  KEYWORD template struct AccumulateAbsDiffWeightedU32<ARCH>; \
  KEYWORD template struct AggregateWindowBoxU16<ARCH>;        \
  KEYWORD template struct AggregateWindowWeightedU32<ARCH>;   \
  KEYWORD template struct NormalizeCostsU16<ARCH>;            \
  KEYWORD template struct NormalizeCostsU32<ARCH>;            \
  KEYWORD template struct DpStep<ARCH>;                       \
  KEYWORD template struct DpStepU16<ARCH>;                    \
  KEYWORD template struct DpPointerU16<ARCH>;                 \
  KEYWORD template struct CensusRowU8<ARCH>;                 \
  KEYWORD template struct CensusWindowU16<ARCH>;              \
  KEYWORD template struct CensusCostsRowU16<ARCH>;            \
  KEYWORD template struct SumRowsU16<ARCH>;                   \
  KEYWORD template struct CensusCostsRowU8<ARCH>;             \
  KEYWORD template struct SumRowsU8<ARCH>;                    \
  KEYWORD template struct NormalizeCostsU8<ARCH>;             \
  KEYWORD template struct PathStepsU16<ARCH>;                 \
  KEYWORD template struct PathStepsU8<ARCH>;                  \
  KEYWORD template struct WinnerU16<ARCH>;                  \
  KEYWORD template struct MinOutsideU16<ARCH>;              \
  KEYWORD template struct AddSaturateU16<ARCH>;             \
  KEYWORD template struct RgbToGrayRowU8<ARCH>;                \
  KEYWORD template struct BgrToGrayRowU8<ARCH>;                \
  KEYWORD template struct Side4TestsU8<ARCH>;                  \
  KEYWORD template struct Side8TestsS32<ARCH>;                 \
  KEYWORD template struct MidpointsRowQ4<ARCH>;               \
  KEYWORD template struct RemapBilinearRowU8<ARCH>;           \
  KEYWORD template struct MidpointsRowConfQ4<ARCH>;

#if defined(__x86_64__) || defined(_M_X64)
TRISTEREO_SIMD_KERNELS_FOR_ARCH(extern, xsimd::sse2)
TRISTEREO_SIMD_KERNELS_FOR_ARCH(extern, xsimd::avx2)
#elif defined(__aarch64__)
TRISTEREO_SIMD_KERNELS_FOR_ARCH(extern, xsimd::neon64)
#elif defined(__arm__)
TRISTEREO_SIMD_KERNELS_FOR_ARCH(extern, xsimd::neon)
#endif

}  // namespace simd
}  // namespace tristereo
