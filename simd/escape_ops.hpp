// Escape hatches: the few lane operations the kernels need that xsimd 8.1.0
// either lacks (mulhi, truncating narrow) or implements badly for our types
// (SSE2 integer min and 16-bit multiply fall back to select chains or a scalar
// loop; AVX2 zip_lo/zip_hi interleave within 128-bit halves, not across).
//
// Every operation has:
//   - a scalar twin on one lane (`*_lane`), which is its exact definition;
//   - a generic version for any Arch, built from xsimd ops or, where xsimd has
//     nothing, by applying the scalar twin lane by lane through memory;
//   - per-arch overrides with intrinsics, selected by tag dispatch on the arch
//     hierarchy (avx2 derives from generic, neon64 from neon), compiled only
//     when the arch's headers are enabled in this translation unit.
// All functions are templates on Arch, so an SSE2 and an AVX2 instantiation are
// distinct symbols and the linker can never merge code built with different
// arch flags. The per-arch kernel tests (tests/simd_kernels_test.cpp) reach
// every override through the kernels and compare them with the scalar kernels.
#pragma once

#include <cstddef>
#include <cstdint>

#include <xsimd/xsimd.hpp>

namespace tristereo {
namespace simd {
namespace escape {

template <class T, class A>
using batch = xsimd::batch<T, A>;

// ---------------------------------------------------------------- scalar twins
// Internal linkage: these are compiled into every arch object with its flags
// and must never be merged across objects by the linker.
namespace {
inline std::uint8_t min_u8_lane(std::uint8_t a, std::uint8_t b) { return a < b ? a : b; }
inline std::uint16_t mullo_u16_lane(std::uint16_t a, std::uint16_t b) {
  return static_cast<std::uint16_t>(std::uint32_t{a} * b);
}
inline std::uint16_t mulhi_u16_lane(std::uint16_t a, std::uint16_t b) {
  return static_cast<std::uint16_t>((std::uint32_t{a} * b) >> 16);
}
// Packed DP keys: plain unsigned min (see min_key below for the SSE2 contract).
inline std::uint32_t min_key_lane(std::uint32_t a, std::uint32_t b) { return a < b ? a : b; }
// Narrowing keeps the low bits (C++ conversion to an unsigned type).
inline std::uint16_t narrow_u32_lane(std::uint32_t a) { return static_cast<std::uint16_t>(a); }
inline std::uint8_t narrow_u16_lane(std::uint16_t a) { return static_cast<std::uint8_t>(a); }
inline std::uint16_t min_u16_lane(std::uint16_t a, std::uint16_t b) { return a < b ? a : b; }
// The dot product of a u32 lane's two u16 halves with b's. Exact (and equal to
// SSE2's signed pmaddwd) while every half is below 2^15: madd_u16's contract.
inline std::uint32_t madd_u16_lane(std::uint32_t a, std::uint32_t b) {
  return (a & 0xFFFF) * (b & 0xFFFF) + (a >> 16) * (b >> 16);
}
}  // namespace

// Lane shifts of u16 batches for the u16 DP scans: lane i takes lane i - S
// (up) or i + S (down); lanes with no source get 0xFFFF, the scans' "no
// candidate" value (it never beats a real value under min).
constexpr std::uint16_t kShiftFillU16 = 0xFFFF;

namespace detail {

// Applies a lane function through memory: the portable fallback.
template <class T, class A, class F>
batch<T, A> apply_lanes(const batch<T, A>& a, const batch<T, A>& b, F f) {
  constexpr std::size_t n = batch<T, A>::size;
  alignas(64) T x[n];
  alignas(64) T y[n];
  a.store_aligned(x);
  b.store_aligned(y);
  for (std::size_t i = 0; i < n; ++i) x[i] = f(x[i], y[i]);
  return batch<T, A>::load_aligned(x);
}

// Two wide batches -> one narrow batch holding their lanes in order, low bits kept.
template <class N, class W, class A, class F>
batch<N, A> narrow_lanes(const batch<W, A>& a, const batch<W, A>& b, F f) {
  constexpr std::size_t n = batch<W, A>::size;
  alignas(64) W x[2 * n];
  alignas(64) N y[2 * n];
  a.store_aligned(x);
  b.store_aligned(x + n);
  for (std::size_t i = 0; i < 2 * n; ++i) y[i] = f(x[i]);
  return batch<N, A>::load_aligned(y);
}

// ---- min of u8
template <class A>
batch<std::uint8_t, A> min_u8(const batch<std::uint8_t, A>& a, const batch<std::uint8_t, A>& b,
                              const xsimd::generic&) {
  return xsimd::min(a, b);  // native on AVX2 and NEON
}
// ---- 16-bit multiply, low half
template <class A>
batch<std::uint16_t, A> mullo_u16(const batch<std::uint16_t, A>& a,
                                  const batch<std::uint16_t, A>& b, const xsimd::generic&) {
  return a * b;  // native on AVX2 and NEON
}
// ---- pairwise 16-bit multiply-add into u32 lanes (madd_u16_lane), from 32-bit
// multiplies: native on NEON; the x86 overrides use pmaddwd
template <class A>
batch<std::uint32_t, A> madd_u16(const batch<std::uint32_t, A>& a, const batch<std::uint32_t, A>& b,
                                 const xsimd::generic&) {
  const batch<std::uint32_t, A> low(0xFFFFu);
  return (a & low) * (b & low) + (a >> 16) * (b >> 16);
}
// ---- 16-bit multiply, high half
template <class A>
batch<std::uint16_t, A> mulhi_u16(const batch<std::uint16_t, A>& a,
                                  const batch<std::uint16_t, A>& b, const xsimd::generic&) {
  return apply_lanes(a, b, mulhi_u16_lane);
}
// ---- min of packed DP keys
template <class A>
batch<std::uint32_t, A> min_key(const batch<std::uint32_t, A>& a,
                                const batch<std::uint32_t, A>& b, const xsimd::generic&) {
  return xsimd::min(a, b);  // native unsigned min on AVX2 and NEON
}
// ---- truncating narrows
template <class A>
batch<std::uint16_t, A> narrow_u32(const batch<std::uint32_t, A>& a,
                                   const batch<std::uint32_t, A>& b, const xsimd::generic&) {
  return narrow_lanes<std::uint16_t>(a, b, narrow_u32_lane);
}
template <class A>
batch<std::uint8_t, A> narrow_u16(const batch<std::uint16_t, A>& a,
                                  const batch<std::uint16_t, A>& b, const xsimd::generic&) {
  return narrow_lanes<std::uint8_t>(a, b, narrow_u16_lane);
}
// ---- min of u16
template <class A>
batch<std::uint16_t, A> min_u16(const batch<std::uint16_t, A>& a,
                                const batch<std::uint16_t, A>& b, const xsimd::generic&) {
  return xsimd::min(a, b);  // native on AVX2 and NEON
}
// ---- the bit count of each byte, in place (SWAR: pairs, nibbles, bytes)
template <class A>
batch<std::uint16_t, A> byte_popcounts_u16(batch<std::uint16_t, A> v, const xsimd::generic&) {
  using b16 = batch<std::uint16_t, A>;
  v = v - ((v >> 1) & b16(std::uint16_t{0x5555}));
  v = (v & b16(std::uint16_t{0x3333})) + ((v >> 2) & b16(std::uint16_t{0x3333}));
  return (v + (v >> 4)) & b16(std::uint16_t{0x0F0F});
}
// ---- each u16 lane's two bytes added
template <class A>
batch<std::uint16_t, A> add_bytes_u16(const batch<std::uint16_t, A>& v, const xsimd::generic&) {
  using b16 = batch<std::uint16_t, A>;
  return (v & b16(std::uint16_t{0x00FF})) + (v >> 8);
}
// ---- u16 lane shifts with 0xFFFF fill, broadcasts of the first / last lane
template <std::size_t S, class A>
batch<std::uint16_t, A> shift_up_u16(const batch<std::uint16_t, A>& a, const xsimd::generic&) {
  constexpr std::size_t n = batch<std::uint16_t, A>::size;
  alignas(64) std::uint16_t x[n];
  alignas(64) std::uint16_t y[n];
  a.store_aligned(x);
  for (std::size_t i = 0; i < n; ++i) y[i] = i >= S ? x[i - S] : kShiftFillU16;
  return batch<std::uint16_t, A>::load_aligned(y);
}
template <std::size_t S, class A>
batch<std::uint16_t, A> shift_down_u16(const batch<std::uint16_t, A>& a, const xsimd::generic&) {
  constexpr std::size_t n = batch<std::uint16_t, A>::size;
  alignas(64) std::uint16_t x[n];
  alignas(64) std::uint16_t y[n];
  a.store_aligned(x);
  for (std::size_t i = 0; i < n; ++i) y[i] = i + S < n ? x[i + S] : kShiftFillU16;
  return batch<std::uint16_t, A>::load_aligned(y);
}
template <class A>
batch<std::uint16_t, A> broadcast_last_u16(const batch<std::uint16_t, A>& a, const xsimd::generic&) {
  alignas(64) std::uint16_t x[batch<std::uint16_t, A>::size];
  a.store_aligned(x);
  return batch<std::uint16_t, A>(x[batch<std::uint16_t, A>::size - 1]);
}
template <class A>
batch<std::uint16_t, A> broadcast_first_u16(const batch<std::uint16_t, A>& a, const xsimd::generic&) {
  alignas(64) std::uint16_t x[batch<std::uint16_t, A>::size];
  a.store_aligned(x);
  return batch<std::uint16_t, A>(x[0]);
}
// ---- order fix before an interleave with zero (widening): identity where
// zip_lo/zip_hi are true full-width interleaves (SSE2, NEON).
template <class T, class A>
batch<T, A> zip_order(const batch<T, A>& a, const xsimd::generic&) {
  return a;
}
// Order fix *after* widening (see widen_unordered): identity where zip_lo and
// zip_hi are full-width interleaves.
template <class T, class A>
void restore_widened_order(batch<T, A>&, batch<T, A>&, const xsimd::generic&) {}

#if XSIMD_WITH_SSE2
template <class A>
batch<std::uint8_t, A> min_u8(const batch<std::uint8_t, A>& a, const batch<std::uint8_t, A>& b,
                              const xsimd::sse2&) {
  return _mm_min_epu8(a, b);
}
template <class A>
batch<std::uint16_t, A> mullo_u16(const batch<std::uint16_t, A>& a,
                                  const batch<std::uint16_t, A>& b, const xsimd::sse2&) {
  return _mm_mullo_epi16(a, b);
}
template <class A>
batch<std::uint16_t, A> mulhi_u16(const batch<std::uint16_t, A>& a,
                                  const batch<std::uint16_t, A>& b, const xsimd::sse2&) {
  return _mm_mulhi_epu16(a, b);
}
// pmaddwd multiplies signed halves: the same as unsigned below 2^15 (the contract).
template <class A>
batch<std::uint32_t, A> madd_u16(const batch<std::uint32_t, A>& a, const batch<std::uint32_t, A>& b,
                                 const xsimd::sse2&) {
  return _mm_madd_epi16(a, b);
}
// SSE2 has no 32-bit min at all (pminud is SSE4.1) and xsimd 8.1 builds the
// unsigned one from two sign flips and a <= made of < and ==. DP keys stay below
// 2^31 (value < 2^23 before the 8-bit index; the kernel adds at most 4 steps
// of 255 * 32000 << 8 on top, see dp_step in kernels-inl.hpp), so a signed
// compare orders them like an unsigned one.
template <class A>
batch<std::uint32_t, A> min_key(const batch<std::uint32_t, A>& a,
                                const batch<std::uint32_t, A>& b, const xsimd::sse2&) {
  const __m128i a_gt_b = _mm_cmpgt_epi32(a, b);
  return _mm_or_si128(_mm_and_si128(a_gt_b, b), _mm_andnot_si128(a_gt_b, a));
}
// packs_epi32 saturates signed values; sign-extending the low 16 bits first
// makes every value representable, so the pack is an exact truncation.
template <class A>
batch<std::uint16_t, A> narrow_u32(const batch<std::uint32_t, A>& a,
                                   const batch<std::uint32_t, A>& b, const xsimd::sse2&) {
  const __m128i a16 = _mm_srai_epi32(_mm_slli_epi32(a, 16), 16);
  const __m128i b16 = _mm_srai_epi32(_mm_slli_epi32(b, 16), 16);
  return _mm_packs_epi32(a16, b16);
}
template <class A>
batch<std::uint8_t, A> narrow_u16(const batch<std::uint16_t, A>& a,
                                  const batch<std::uint16_t, A>& b, const xsimd::sse2&) {
  const __m128i low = _mm_set1_epi16(0x00ff);
  return _mm_packus_epi16(_mm_and_si128(a, low), _mm_and_si128(b, low));
}
// SSE2 has no u16 min (pminuw is SSE4.1): a - (a -sat b) = min(a, b).
template <class A>
batch<std::uint16_t, A> min_u16(const batch<std::uint16_t, A>& a,
                                const batch<std::uint16_t, A>& b, const xsimd::sse2&) {
  return _mm_sub_epi16(a, _mm_subs_epu16(a, b));
}
// Byte shifts bring in zeros; OR-ing the vacated lanes with ones makes them 0xFFFF.
template <std::size_t S, class A>
batch<std::uint16_t, A> shift_up_u16(const batch<std::uint16_t, A>& a, const xsimd::sse2&) {
  const __m128i fill = _mm_srli_si128(_mm_set1_epi32(-1), 16 - 2 * S);
  return _mm_or_si128(_mm_slli_si128(a, 2 * S), fill);
}
template <std::size_t S, class A>
batch<std::uint16_t, A> shift_down_u16(const batch<std::uint16_t, A>& a, const xsimd::sse2&) {
  const __m128i fill = _mm_slli_si128(_mm_set1_epi32(-1), 16 - 2 * S);
  return _mm_or_si128(_mm_srli_si128(a, 2 * S), fill);
}
template <class A>
batch<std::uint16_t, A> broadcast_last_u16(const batch<std::uint16_t, A>& a, const xsimd::sse2&) {
  const __m128i hi = _mm_shufflehi_epi16(a, 0xFF);
  return _mm_unpackhi_epi64(hi, hi);
}
template <class A>
batch<std::uint16_t, A> broadcast_first_u16(const batch<std::uint16_t, A>& a, const xsimd::sse2&) {
  const __m128i lo = _mm_shufflelo_epi16(a, 0x00);
  return _mm_unpacklo_epi64(lo, lo);
}
#endif

#if XSIMD_WITH_AVX2
template <class A>
batch<std::uint16_t, A> mulhi_u16(const batch<std::uint16_t, A>& a,
                                  const batch<std::uint16_t, A>& b, const xsimd::avx2&) {
  return _mm256_mulhi_epu16(a, b);
}
template <class A>
batch<std::uint32_t, A> madd_u16(const batch<std::uint32_t, A>& a, const batch<std::uint32_t, A>& b,
                                 const xsimd::avx2&) {
  return _mm256_madd_epi16(a, b);
}
// Each byte's bit count from a 16-entry nibble table (vpshufb); a lane's two
// bytes added by vpmaddubsw with weights 1.
template <class A>
batch<std::uint16_t, A> byte_popcounts_u16(const batch<std::uint16_t, A>& v, const xsimd::avx2&) {
  const __m256i table = _mm256_setr_epi8(0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4,
                                         0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4);
  const __m256i nibble = _mm256_set1_epi8(0x0F);
  const __m256i lo = _mm256_shuffle_epi8(table, _mm256_and_si256(v, nibble));
  const __m256i hi = _mm256_shuffle_epi8(table, _mm256_and_si256(_mm256_srli_epi16(v, 4), nibble));
  return _mm256_add_epi8(lo, hi);
}
template <class A>
batch<std::uint16_t, A> add_bytes_u16(const batch<std::uint16_t, A>& v, const xsimd::avx2&) {
  return _mm256_maddubs_epi16(v, _mm256_set1_epi8(1));
}
// AVX2 packs work within each 128-bit half; the qword permute (0, 2, 1, 3)
// puts the halves back in lane order.
constexpr int kQwordOrder0213 = 0xD8;
template <class A>
batch<std::uint16_t, A> narrow_u32(const batch<std::uint32_t, A>& a,
                                   const batch<std::uint32_t, A>& b, const xsimd::avx2&) {
  const __m256i a16 = _mm256_srai_epi32(_mm256_slli_epi32(a, 16), 16);
  const __m256i b16 = _mm256_srai_epi32(_mm256_slli_epi32(b, 16), 16);
  return _mm256_permute4x64_epi64(_mm256_packs_epi32(a16, b16), kQwordOrder0213);
}
template <class A>
batch<std::uint8_t, A> narrow_u16(const batch<std::uint16_t, A>& a,
                                  const batch<std::uint16_t, A>& b, const xsimd::avx2&) {
  const __m256i low = _mm256_set1_epi16(0x00ff);
  return _mm256_permute4x64_epi64(
      _mm256_packus_epi16(_mm256_and_si256(a, low), _mm256_and_si256(b, low)), kQwordOrder0213);
}
// xsimd 8.1's AVX2 zip_lo/zip_hi are the in-lane unpacks: zip_lo(x, 0) widens
// elements 0-7 and 16-23. Pre-permuting the qwords makes them a true widening.
template <class T, class A>
batch<T, A> zip_order(const batch<T, A>& a, const xsimd::avx2&) {
  return _mm256_permute4x64_epi64(a, kQwordOrder0213);
}
// The inverse of the in-lane interleave: after lo' = zip_lo(x, 0) and
// hi' = zip_hi(x, 0) on AVX2, lo' holds elements {0..n/4-1, n/2..3n/4-1} of the
// widened x and hi' the rest; swapping their upper and lower 128-bit halves
// restores lo = widened elements 0..n/2-1, hi = n/2..n-1.
template <class T, class A>
void restore_widened_order(batch<T, A>& lo, batch<T, A>& hi, const xsimd::avx2&) {
  const __m256i a = lo, b = hi;
  lo = _mm256_permute2x128_si256(a, b, 0x20);
  hi = _mm256_permute2x128_si256(a, b, 0x31);
}
// 256-bit lane shifts cross the 128-bit halves: permute2x128 supplies the
// neighbouring half (or zero), alignr shifts the pair; S = 8 is the permute alone.
template <std::size_t S, class A>
batch<std::uint16_t, A> shift_up_u16(const batch<std::uint16_t, A>& a, const xsimd::avx2&) {
  static_assert(S >= 1 && S <= 8, "shift of 1 .. 8 u16 lanes");
  const __m256i below = _mm256_permute2x128_si256(a, a, 0x08);  // (0, a.lo)
  __m256i shifted;
  if constexpr (S == 8) {
    shifted = below;
  } else {
    shifted = _mm256_alignr_epi8(a, below, 16 - 2 * S);
  }
  alignas(32) static constexpr std::uint16_t kFill[32] = {
      0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF,
      0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF};
  // lanes 0 .. S-1 of the fill are ones: a load at kFill + 16 - S.
  return _mm256_or_si256(shifted,
                         _mm256_loadu_si256(reinterpret_cast<const __m256i*>(kFill + 16 - S)));
}
template <std::size_t S, class A>
batch<std::uint16_t, A> shift_down_u16(const batch<std::uint16_t, A>& a, const xsimd::avx2&) {
  static_assert(S >= 1 && S <= 8, "shift of 1 .. 8 u16 lanes");
  const __m256i above = _mm256_permute2x128_si256(a, a, 0x81);  // (a.hi, 0)
  __m256i shifted;
  if constexpr (S == 8) {
    shifted = above;
  } else {
    shifted = _mm256_alignr_epi8(above, a, 2 * S);
  }
  alignas(32) static constexpr std::uint16_t kFill[32] = {
      0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
      0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF,
      0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF};
  // lanes 16-S .. 15 of the fill are ones: a load at kFill + S.
  return _mm256_or_si256(shifted, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(kFill + S)));
}
template <class A>
batch<std::uint16_t, A> broadcast_last_u16(const batch<std::uint16_t, A>& a, const xsimd::avx2&) {
  return _mm256_broadcastw_epi16(_mm_srli_si128(_mm256_extracti128_si256(a, 1), 14));
}
template <class A>
batch<std::uint16_t, A> broadcast_first_u16(const batch<std::uint16_t, A>& a, const xsimd::avx2&) {
  return _mm256_broadcastw_epi16(_mm256_castsi256_si128(a));
}
#endif

#if XSIMD_WITH_NEON
// vcnt counts the bits of each byte; the pairwise widening add sums each u16's two.
template <class A>
batch<std::uint16_t, A> byte_popcounts_u16(const batch<std::uint16_t, A>& v, const xsimd::neon&) {
  return vreinterpretq_u16_u8(vcntq_u8(vreinterpretq_u8_u16(v)));
}
template <class A>
batch<std::uint16_t, A> add_bytes_u16(const batch<std::uint16_t, A>& v, const xsimd::neon&) {
  return vpaddlq_u8(vreinterpretq_u8_u16(v));
}
template <class A>
batch<std::uint16_t, A> mulhi_u16(const batch<std::uint16_t, A>& a,
                                  const batch<std::uint16_t, A>& b, const xsimd::neon&) {
  const uint32x4_t lo = vmull_u16(vget_low_u16(a), vget_low_u16(b));
  const uint32x4_t hi = vmull_u16(vget_high_u16(a), vget_high_u16(b));
  return vcombine_u16(vshrn_n_u32(lo, 16), vshrn_n_u32(hi, 16));
}
template <class A>
batch<std::uint16_t, A> narrow_u32(const batch<std::uint32_t, A>& a,
                                   const batch<std::uint32_t, A>& b, const xsimd::neon&) {
  return vcombine_u16(vmovn_u32(a), vmovn_u32(b));
}
template <class A>
batch<std::uint8_t, A> narrow_u16(const batch<std::uint16_t, A>& a,
                                  const batch<std::uint16_t, A>& b, const xsimd::neon&) {
  return vcombine_u8(vmovn_u16(a), vmovn_u16(b));
}
// vext takes the top lanes of its first operand, so a 0xFFFF vector there
// is the fill (works on ARMv7 and AArch64 alike).
template <std::size_t S, class A>
batch<std::uint16_t, A> shift_up_u16(const batch<std::uint16_t, A>& a, const xsimd::neon&) {
  return vextq_u16(vdupq_n_u16(kShiftFillU16), a, 8 - S);
}
template <std::size_t S, class A>
batch<std::uint16_t, A> shift_down_u16(const batch<std::uint16_t, A>& a, const xsimd::neon&) {
  return vextq_u16(a, vdupq_n_u16(kShiftFillU16), S);
}
template <class A>
batch<std::uint16_t, A> broadcast_last_u16(const batch<std::uint16_t, A>& a, const xsimd::neon&) {
  return vdupq_lane_u16(vget_high_u16(a), 3);
}
template <class A>
batch<std::uint16_t, A> broadcast_first_u16(const batch<std::uint16_t, A>& a, const xsimd::neon&) {
  return vdupq_lane_u16(vget_low_u16(a), 0);
}
#endif

// ---- smallest u16 lane. It ends every path step and feeds the next one's
// penalties, so its latency is on the path's dependency chain: halving lanes
// with shifts takes log2(lanes) dependent shuffle + min pairs; AVX2 has
// phminposuw for the last 8, AArch64 a single across-vector min.
template <class A>
std::uint16_t hmin_u16(batch<std::uint16_t, A> x, const xsimd::generic&) {
  constexpr std::size_t lanes = batch<std::uint16_t, A>::size;
  if constexpr (lanes > 8) x = min_u16(x, shift_down_u16<8>(x, A{}), A{});
  x = min_u16(x, shift_down_u16<4>(x, A{}), A{});
  x = min_u16(x, shift_down_u16<2>(x, A{}), A{});
  x = min_u16(x, shift_down_u16<1>(x, A{}), A{});
  alignas(64) std::uint16_t lane[lanes];
  x.store_aligned(lane);
  return lane[0];
}
#if XSIMD_WITH_AVX2
template <class A>
std::uint16_t hmin_u16(const batch<std::uint16_t, A>& x, const xsimd::avx2&) {
  const __m256i v = x;
  const __m128i m = _mm_min_epu16(_mm256_castsi256_si128(v), _mm256_extracti128_si256(v, 1));
  return static_cast<std::uint16_t>(_mm_cvtsi128_si32(_mm_minpos_epu16(m)));
}
#endif
#if XSIMD_WITH_NEON64
template <class A>
std::uint16_t hmin_u16(const batch<std::uint16_t, A>& x, const xsimd::neon64&) {
  return vminvq_u16(x);
}
#elif XSIMD_WITH_NEON
template <class A>
std::uint16_t hmin_u16(const batch<std::uint16_t, A>& x, const xsimd::neon&) {
  uint16x4_t m = vmin_u16(vget_low_u16(x), vget_high_u16(x));
  m = vpmin_u16(m, m);
  m = vpmin_u16(m, m);
  return vget_lane_u16(m, 0);
}
#endif

// ---- the even and odd lanes of 2 N consecutive int32 (N doubles per
// register), as doubles: the scalar loop is the definition.
template <class A>
void even_odd_s32_to_f64(const std::int32_t* p, batch<double, A>& even, batch<double, A>& odd,
                         const xsimd::generic&) {
  constexpr std::size_t n = batch<double, A>::size;
  alignas(64) double e[n], o[n];
  for (std::size_t i = 0; i < n; ++i) e[i] = p[2 * i], o[i] = p[2 * i + 1];
  even = batch<double, A>::load_aligned(e);
  odd = batch<double, A>::load_aligned(o);
}
#if XSIMD_WITH_SSE2
template <class A>
void even_odd_s32_to_f64(const std::int32_t* p, batch<double, A>& even, batch<double, A>& odd,
                         const xsimd::sse2&) {
  const __m128i v = _mm_shuffle_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)), 0xD8);  // e0 e1 o0 o1
  even = _mm_cvtepi32_pd(v);
  odd = _mm_cvtepi32_pd(_mm_unpackhi_epi64(v, v));
}
#endif
#if XSIMD_WITH_AVX2
template <class A>
void even_odd_s32_to_f64(const std::int32_t* p, batch<double, A>& even, batch<double, A>& odd,
                         const xsimd::avx2&) {
  const __m256i v = _mm256_permutevar8x32_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)),
                                                _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7));
  even = _mm256_cvtepi32_pd(_mm256_castsi256_si128(v));
  odd = _mm256_cvtepi32_pd(_mm256_extracti128_si256(v, 1));
}
#endif
#if XSIMD_WITH_NEON64
template <class A>
void even_odd_s32_to_f64(const std::int32_t* p, batch<double, A>& even, batch<double, A>& odd,
                         const xsimd::neon64&) {
  const int32x4_t v = vld1q_s32(p);
  even = vcvtq_f64_s64(vmovl_s32(vget_low_s32(vuzp1q_s32(v, v))));
  odd = vcvtq_f64_s64(vmovl_s32(vget_low_s32(vuzp2q_s32(v, v))));
}
#endif

// ---- p[8 l + K] of lanes l (N doubles per register) as doubles, reading
// only p[0 .. 8 N - 1]: the bytes sit at the bottom of 64-bit lanes after a
// shift, and a byte b becomes a double as the bits of 2^52 + b, less 2^52.
template <int K, class A>
batch<double, A> bytes_every_8_to_f64(const std::uint8_t* p, const xsimd::generic&) {
  constexpr std::size_t n = batch<double, A>::size;
  alignas(64) double v[n];
  for (std::size_t i = 0; i < n; ++i) v[i] = p[8 * i + K];
  return batch<double, A>::load_aligned(v);
}
// ---- lanes 1 .. N - 1 of v, then `last`
template <class A>
batch<double, A> shift_in_last_f64(const batch<double, A>& v, double last, const xsimd::generic&) {
  constexpr std::size_t n = batch<double, A>::size;
  alignas(64) double t[n + 1];
  v.store_aligned(t);
  t[n] = last;
  return batch<double, A>::load_unaligned(t + 1);
}
// ---- integer-valued doubles stored as int32 (N of them)
template <class A>
void store_f64_as_s32(std::int32_t* p, const batch<double, A>& v, const xsimd::generic&) {
  constexpr std::size_t n = batch<double, A>::size;
  alignas(64) double t[n];
  v.store_aligned(t);
  for (std::size_t i = 0; i < n; ++i) p[i] = static_cast<std::int32_t>(t[i]);
}
constexpr std::uint64_t kTwo52Bits = 0x4330000000000000ull;  // the double 2^52
#if XSIMD_WITH_SSE2
template <int K, class A>
batch<double, A> bytes_every_8_to_f64(const std::uint8_t* p, const xsimd::sse2&) {
  const __m128i v = _mm_srli_epi64(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)), 8 * K);
  const __m128i bits = _mm_or_si128(_mm_and_si128(v, _mm_set1_epi64x(0xFF)),
                                    _mm_set1_epi64x(static_cast<long long>(kTwo52Bits)));
  return _mm_sub_pd(_mm_castsi128_pd(bits), _mm_set1_pd(4503599627370496.0));
}
template <class A>
batch<double, A> shift_in_last_f64(const batch<double, A>& v, double last, const xsimd::sse2&) {
  return _mm_shuffle_pd(v, _mm_set1_pd(last), 1);
}
template <class A>
void store_f64_as_s32(std::int32_t* p, const batch<double, A>& v, const xsimd::sse2&) {
  _mm_storel_epi64(reinterpret_cast<__m128i*>(p), _mm_cvttpd_epi32(v));
}
#endif
#if XSIMD_WITH_AVX2
template <int K, class A>
batch<double, A> bytes_every_8_to_f64(const std::uint8_t* p, const xsimd::avx2&) {
  const __m256i v = _mm256_srli_epi64(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)), 8 * K);
  const __m256i bits = _mm256_or_si256(_mm256_and_si256(v, _mm256_set1_epi64x(0xFF)),
                                       _mm256_set1_epi64x(static_cast<long long>(kTwo52Bits)));
  return _mm256_sub_pd(_mm256_castsi256_pd(bits), _mm256_set1_pd(4503599627370496.0));
}
template <class A>
batch<double, A> shift_in_last_f64(const batch<double, A>& v, double last, const xsimd::avx2&) {
  return _mm256_blend_pd(_mm256_permute4x64_pd(v, 0xF9), _mm256_set1_pd(last), 0x8);  // (v1, v2, v3, last)
}
template <class A>
void store_f64_as_s32(std::int32_t* p, const batch<double, A>& v, const xsimd::avx2&) {
  _mm_storeu_si128(reinterpret_cast<__m128i*>(p), _mm256_cvttpd_epi32(v));
}
#endif
#if XSIMD_WITH_NEON64
template <int K, class A>
batch<double, A> bytes_every_8_to_f64(const std::uint8_t* p, const xsimd::neon64&) {
  uint64x2_t v = vreinterpretq_u64_u8(vld1q_u8(p));
  if constexpr (K > 0) v = vshrq_n_u64(v, 8 * K);  // a shift of 1 .. 64
  return vcvtq_f64_u64(vandq_u64(v, vdupq_n_u64(0xFF)));
}
template <class A>
batch<double, A> shift_in_last_f64(const batch<double, A>& v, double last, const xsimd::neon64&) {
  return vextq_f64(v, vdupq_n_f64(last), 1);
}
template <class A>
void store_f64_as_s32(std::int32_t* p, const batch<double, A>& v, const xsimd::neon64&) {
  vst1_s32(p, vmovn_s64(vcvtq_s64_f64(v)));
}
#endif

// ---- (a b + 2^14) >> 15 for lanes a, b < 2^15: a rounding multiply-high.
// With P = a b = hi 2^16 + lo, (P + 2^14) >> 15 = 2 hi + ((lo + 2^14) >> 15),
// and the last term is ((lo >> 14) + 1) >> 1 without leaving 16 bits.
// AVX2's pmulhrsw and NEON's vqrdmulh are this product on signed lanes, which
// a, b < 2^15 keep non-negative (no saturation).
template <class A>
batch<std::uint16_t, A> mulhrs_u15(const batch<std::uint16_t, A>& a, const batch<std::uint16_t, A>& b,
                                   const xsimd::generic&) {
  const batch<std::uint16_t, A> hi = mulhi_u16(a, b, A{}), lo = mullo_u16(a, b, A{});
  return (hi << 1) + (((lo >> 14) + batch<std::uint16_t, A>(std::uint16_t{1})) >> 1);
}
#if XSIMD_WITH_AVX2
template <class A>
batch<std::uint16_t, A> mulhrs_u15(const batch<std::uint16_t, A>& a, const batch<std::uint16_t, A>& b,
                                   const xsimd::avx2&) {
  return _mm256_mulhrs_epi16(a, b);
}
#endif
#if XSIMD_WITH_NEON
template <class A>
batch<std::uint16_t, A> mulhrs_u15(const batch<std::uint16_t, A>& a, const batch<std::uint16_t, A>& b,
                                   const xsimd::neon&) {
  return vreinterpretq_u16_s16(vqrdmulhq_s16(vreinterpretq_s16_u16(a), vreinterpretq_s16_u16(b)));
}
#endif

// ---- the u16 lanes' count of bytes from p, zero-extended in order (a byte
// cost row read straight into u16 arithmetic; the loop is the definition).
template <class A>
batch<std::uint16_t, A> load_widen_u8(const std::uint8_t* p, const xsimd::generic&) {
  constexpr std::size_t lanes = batch<std::uint16_t, A>::size;
  alignas(64) std::uint16_t w[lanes];
  for (std::size_t i = 0; i < lanes; ++i) w[i] = p[i];
  return batch<std::uint16_t, A>::load_aligned(w);
}
#if XSIMD_WITH_SSE2
template <class A>
batch<std::uint16_t, A> load_widen_u8(const std::uint8_t* p, const xsimd::sse2&) {
  return _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)), _mm_setzero_si128());
}
#endif
#if XSIMD_WITH_AVX2
template <class A>
batch<std::uint16_t, A> load_widen_u8(const std::uint8_t* p, const xsimd::avx2&) {
  return _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)));
}
#endif
#if XSIMD_WITH_NEON
template <class A>
batch<std::uint16_t, A> load_widen_u8(const std::uint8_t* p, const xsimd::neon&) {
  return vmovl_u8(vld1_u8(p));
}
#endif

}  // namespace detail

// ---------------------------------------------------------------- public escapes
// (a b + 2^14) >> 15 per lane; every lane of a and b below 2^15.
template <class A>
batch<std::uint16_t, A> mulhrs_u15(const batch<std::uint16_t, A>& a, const batch<std::uint16_t, A>& b) {
  return detail::mulhrs_u15(a, b, A{});
}
// Reads batch<std::uint16_t, A>::size bytes.
template <class A>
batch<std::uint16_t, A> load_widen_u8(const std::uint8_t* p) {
  return detail::load_widen_u8<A>(p, A{});
}
template <class A>
batch<std::uint8_t, A> min_u8(const batch<std::uint8_t, A>& a, const batch<std::uint8_t, A>& b) {
  return detail::min_u8(a, b, A{});
}
template <class A>
batch<std::uint16_t, A> mullo_u16(const batch<std::uint16_t, A>& a,
                                  const batch<std::uint16_t, A>& b) {
  return detail::mullo_u16(a, b, A{});
}
template <class A>
batch<std::uint16_t, A> mulhi_u16(const batch<std::uint16_t, A>& a,
                                  const batch<std::uint16_t, A>& b) {
  return detail::mulhi_u16(a, b, A{});
}
// Lane i: a's low half times b's low half plus a's high half times b's high
// half (madd_u16_lane). Every 16-bit half of a and b must be below 2^15.
template <class A>
batch<std::uint32_t, A> madd_u16(const batch<std::uint32_t, A>& a, const batch<std::uint32_t, A>& b) {
  return detail::madd_u16(a, b, A{});
}
template <class A>
batch<std::uint32_t, A> min_key(const batch<std::uint32_t, A>& a,
                                const batch<std::uint32_t, A>& b) {
  return detail::min_key(a, b, A{});
}
template <class A>
batch<std::uint16_t, A> narrow_u32(const batch<std::uint32_t, A>& a,
                                   const batch<std::uint32_t, A>& b) {
  return detail::narrow_u32(a, b, A{});
}
template <class A>
batch<std::uint8_t, A> narrow_u16(const batch<std::uint16_t, A>& a,
                                  const batch<std::uint16_t, A>& b) {
  return detail::narrow_u16(a, b, A{});
}

template <class A>
batch<std::uint16_t, A> min_u16(const batch<std::uint16_t, A>& a,
                                const batch<std::uint16_t, A>& b) {
  return detail::min_u16(a, b, A{});
}
// Each byte of each lane replaced by its bit count; add_bytes_u16 adds a
// lane's two bytes. popcount_u16 is the two in a row: counts of several words
// can be added as bytes first (while every byte stays below 256) and their
// bytes added once.
template <class A>
batch<std::uint16_t, A> byte_popcounts_u16(const batch<std::uint16_t, A>& v) {
  return detail::byte_popcounts_u16(v, A{});
}
template <class A>
batch<std::uint16_t, A> add_bytes_u16(const batch<std::uint16_t, A>& v) {
  return detail::add_bytes_u16(v, A{});
}
// popcount(v) of each lane: SWAR (SSE2), nibble table (AVX2), vcnt (NEON).
template <class A>
batch<std::uint16_t, A> popcount_u16(const batch<std::uint16_t, A>& v) {
  return add_bytes_u16(byte_popcounts_u16(v));
}
// The bit count of each byte lane (the census's byte planes): byte_popcounts_u16
// counts each byte on its own.
template <class A>
batch<std::uint8_t, A> popcount_u8(const batch<std::uint8_t, A>& v) {
  return xsimd::bitwise_cast<batch<std::uint8_t, A>>(byte_popcounts_u16(xsimd::bitwise_cast<batch<std::uint16_t, A>>(v)));
}
template <std::size_t S, class A>
batch<std::uint16_t, A> shift_up_u16(const batch<std::uint16_t, A>& a) {
  return detail::shift_up_u16<S>(a, A{});
}
template <std::size_t S, class A>
batch<std::uint16_t, A> shift_down_u16(const batch<std::uint16_t, A>& a) {
  return detail::shift_down_u16<S>(a, A{});
}
template <class A>
batch<std::uint16_t, A> broadcast_last_u16(const batch<std::uint16_t, A>& a) {
  return detail::broadcast_last_u16(a, A{});
}
template <class A>
batch<std::uint16_t, A> broadcast_first_u16(const batch<std::uint16_t, A>& a) {
  return detail::broadcast_first_u16(a, A{});
}
// The smallest lane of a.
template <class A>
std::uint16_t hmin_u16(const batch<std::uint16_t, A>& a) {
  return detail::hmin_u16(a, A{});
}

// Widens unsigned lanes to twice their width: lo gets elements 0 .. n/2-1,
// hi gets n/2 .. n-1 (zip with zero, little-endian lane layout).
template <class T, class W, class A>
void widen(const batch<T, A>& a, batch<W, A>& lo, batch<W, A>& hi) {
  static_assert(sizeof(W) == 2 * sizeof(T), "widen doubles the lane width");
  const batch<T, A> ordered = detail::zip_order(a, A{});
  const batch<T, A> zero(T{0});
  lo = xsimd::bitwise_cast<batch<W, A>>(xsimd::zip_lo(ordered, zero));
  hi = xsimd::bitwise_cast<batch<W, A>>(xsimd::zip_hi(ordered, zero));
}

// The u16 words lo[i] | hi[i] << 8, in order: i < n/2 in first, the rest in second.
template <class A>
void interleave_bytes(const batch<std::uint8_t, A>& lo, const batch<std::uint8_t, A>& hi,
                      batch<std::uint16_t, A>& first, batch<std::uint16_t, A>& second) {
  const batch<std::uint8_t, A> l = detail::zip_order(lo, A{}), h = detail::zip_order(hi, A{});
  first = xsimd::bitwise_cast<batch<std::uint16_t, A>>(xsimd::zip_lo(l, h));
  second = xsimd::bitwise_cast<batch<std::uint16_t, A>>(xsimd::zip_hi(l, h));
}

// widen() without its order fix, for sums: lo and hi hold the widened
// elements in an arch-defined permutation (in-lane halves on AVX2, none on
// SSE2/NEON). Lane-wise sums of such pairs keep that permutation, so a kernel
// can accumulate many of them and call restore_widened_order once at the end:
// restore_widened_order(widen_unordered(a)) == widen(a).
template <class T, class W, class A>
void widen_unordered(const batch<T, A>& a, batch<W, A>& lo, batch<W, A>& hi) {
  static_assert(sizeof(W) == 2 * sizeof(T), "widen doubles the lane width");
  const batch<T, A> zero(T{0});
  lo = xsimd::bitwise_cast<batch<W, A>>(xsimd::zip_lo(a, zero));
  hi = xsimd::bitwise_cast<batch<W, A>>(xsimd::zip_hi(a, zero));
}
template <class W, class A>
void restore_widened_order(batch<W, A>& lo, batch<W, A>& hi) {
  detail::restore_widened_order(lo, hi, A{});
}

// p[8 l + K] for lanes l, as doubles (reads p[0 .. 8 N - 1]).
template <int K, class A>
batch<double, A> bytes_every_8_to_f64(const std::uint8_t* p) {
  static_assert(K >= 0 && K < 8, "a byte of each 8");
  return detail::bytes_every_8_to_f64<K, A>(p, A{});
}
// (v[1], ..., v[N - 1], last).
template <class A>
batch<double, A> shift_in_last_f64(const batch<double, A>& v, double last) {
  return detail::shift_in_last_f64(v, last, A{});
}
// The N lanes of v, integers within int32, to p[0 .. N - 1].
template <class A>
void store_f64_as_s32(std::int32_t* p, const batch<double, A>& v) {
  detail::store_f64_as_s32(p, v, A{});
}
// even = p[0], p[2], ..., odd = p[1], p[3], ... (2 N int32 read), as doubles.
template <class A>
void even_odd_s32_to_f64(const std::int32_t* p, batch<double, A>& even, batch<double, A>& odd) {
  detail::even_odd_s32_to_f64(p, even, odd, A{});
}

}  // namespace escape
}  // namespace simd
}  // namespace tristereo
