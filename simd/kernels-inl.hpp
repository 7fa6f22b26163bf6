// Bodies of the SIMD kernels declared in simd/kernels.hpp. Included only by
// simd/arch_<arch>.cpp, each compiled with its own arch flags.
//
// Conventions shared by all kernels:
//   - Pointers are arbitrary (unaligned); n is any value in 1 .. 256.
//   - Tails: full blocks run straight from the caller's memory. When n is at
//     least a block, the remainder of the census, path, selection, DP and
//     normalisation kernels is the full block ending at n, overlapping the
//     last one: its first lanes write the same values again (no output is an
//     input) or meet a min twice; an accumulated sum adds to the old values
//     read first (PathStepU16, WinnerU16's right view); the DP's scans start it from their
//     exact values just outside it (DpStepU16). Otherwise (n below a block,
//     and the accumulating cost kernels) the remainder goes to the narrower
//     instantiation or runs the *same* block code once more on padded stack
//     copies, copying back only the valid part (libyuv's "any" pattern).
//     There is no second tail algorithm, and nothing is read or written past n.
//   - Lane layout is little-endian (x86, AArch64, ARMv7 little-endian): the
//     low 16 bits of a u32 lane are the even u16 lane of the same register.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include <xsimd/xsimd.hpp>

#include "simd/escape_ops.hpp"
#include "simd/kernels.hpp"
#include "src/kernels/kernel_set.hpp"
#include "src/kernels/kernels_scalar.hpp"
#include "src/tritree/side4_shapes.hpp"
#include "src/tritree/side8_shapes.hpp"

namespace tristereo {
namespace simd {
namespace detail {

template <class T, class A>
using batch = xsimd::batch<T, A>;

// Largest n any kernel is given (D <= 256, docs/model.md section 5).
constexpr int kMaxLanes = 256;

// The same kernel one register width down, for remainders too short for a
// full register: AVX2 hands them to the SSE2 instantiation (always compiled
// beside it on x86-64) instead of padding 31 elements out to 32. `void` = none.
template <class A>
struct Narrower {
  using type = void;
};
template <>
struct Narrower<xsimd::avx2> {
  using type = xsimd::sse2;
};

// Runs block(in + k, io + k) over every full block of Lanes elements. The
// remainder goes to narrow(in + k, io + k, m) when the arch has a narrower
// twin (pass nullptr otherwise), else the same block runs once more on padded
// copies. `io` is read and written (accumulators) or only written (outputs);
// either way only its first n elements are touched.
template <int Lanes, class In, class Io, class Block, class Narrow>
void for_blocks(const In* in, int n, Io* io, Block block, Narrow narrow) {
  int k = 0;
  for (; k + Lanes <= n; k += Lanes) block(in + k, io + k);
  if (k == n) return;
  if constexpr (!std::is_same<Narrow, std::nullptr_t>::value) {
    narrow(in + k, io + k, n - k);
  } else {
    const std::size_t m = static_cast<std::size_t>(n - k);
    alignas(64) In in_pad[Lanes] = {};
    alignas(64) Io io_pad[Lanes] = {};
    std::memcpy(in_pad, in + k, m * sizeof(In));
    std::memcpy(io_pad, io + k, m * sizeof(Io));
    block(in_pad, io_pad);
    std::memcpy(io + k, io_pad, m * sizeof(Io));
  }
}

// for_blocks for kernels whose io is only written and is not in: when n is at
// least a block, the remainder is the full block ending at n (its first lanes
// write the same values again), with no narrower call and no copies.
template <int Lanes, class In, class Io, class Block, class Narrow>
void for_output_blocks(const In* in, int n, Io* io, Block block, Narrow narrow) {
  if (n < Lanes || n % Lanes == 0) return for_blocks<Lanes>(in, n, io, block, narrow);
  int k = 0;
  for (; k + Lanes <= n; k += Lanes) block(in + k, io + k);
  block(in + n - Lanes, io + n - Lanes);
}

// A call too short for a register: Kernel<Narrower<A>> when there is one,
// else the scalar twin.
template <template <class> class Kernel, class A, class Scalar, class... Args>
void narrower_or_scalar(Scalar scalar, Args... args) {
  using Half = typename Narrower<A>::type;
  if constexpr (!std::is_void<Half>::value) {
    (void)scalar;
    Kernel<Half>::call(args...);
  } else {
    scalar(args...);
  }
}

// nullptr, or a lambda forwarding a remainder to Kernel<Narrower<A>>.
template <template <class> class Kernel, class A, class Fwd>
auto narrower_or_null(Fwd fwd) {
  using Half = typename Narrower<A>::type;
  if constexpr (std::is_void<Half>::value) {
    (void)fwd;
    return nullptr;
  } else {
    return [fwd](auto in, auto io, int m) { fwd(&Kernel<Half>::call, in, io, m); };
  }
}

// min(|left - right|, trunc) on u8 lanes: |a - b| = (a -sat b) | (b -sat a),
// one of which is zero.
template <class A>
batch<std::uint8_t, A> truncated_abs_diff(const batch<std::uint8_t, A>& left,
                                          const batch<std::uint8_t, A>& right,
                                          const batch<std::uint8_t, A>& trunc) {
  return escape::min_u8(xsimd::ssub(left, right) | xsimd::ssub(right, left), trunc);
}

// ---- Q32 reciprocal normalisation, exactly as the scalar 64-bit expression.
// cost = bits 32..47 of (sum * inv * 16 + 2^31) mod 2^64
//      = bits 28..43 of (p + 2^27), p = sum * inv   (mod 2^60 changes none of them).
// With 16-bit limbs sum = s0 + s1 2^16 and inv = i0 + i1 2^16 + i2 2^32 (+ higher
// limbs, which only reach bits >= 48), p is a sum of 16x16 -> 32-bit products
// placed at columns of 2^16. Let col1 be everything landing at 2^16 (plus the
// rounding 2^27 = 2^11 * 2^16) and col2 everything at 2^32; the column at 2^0
// is < 2^16 and carries nothing. Then
//   cost = ((col1 >> 12) + (col2 << 4)) mod 2^16,
// and col2 is only needed mod 2^12, so products at 2^48 and above drop out.
constexpr int kLimbBits = 16;
constexpr int kColumnShift = 12;                    // 28 - kLimbBits
constexpr std::uint32_t kColumnHalf = 1u << 11;     // 2^27 / 2^kLimbBits
constexpr std::uint32_t kColumnLow = (1u << kColumnShift) - 1;
constexpr std::uint32_t kLimbMask = 0xffffu;
constexpr int kCol2Shift = kLimbBits - kColumnShift;  // 4: (col2 * 2^32) >> 28

// ---- DP keys: (value << 8) | index, as in src/dp/dp_kernels_scalar.cpp.
constexpr int kIndexBits = 8;
// Value written into the lanes past n of the last batch. Real keys are at most
// ((4080 + 255 * 32000) << 8) | 255 = 2'089'996'735 < kPadKey, so pad lanes never
// win a min against a real key, and kPadKey plus four penalty steps
// (4 * 32000 << 8) stays below 2^31 (the SSE2 signed-min contract).
constexpr std::uint32_t kPadKey = 0x7D000000u;

// Lane-index generators for xsimd::make_batch_constant.
template <std::size_t S>
struct ShiftUpIdx {  // lane i takes lane i - S; the first S lanes keep their own
  static constexpr std::uint32_t get(std::size_t i, std::size_t) {
    return static_cast<std::uint32_t>(i >= S ? i - S : i);
  }
};
template <std::size_t S>
struct ShiftDownIdx {  // lane i takes lane i + S; the last S lanes keep their own
  static constexpr std::uint32_t get(std::size_t i, std::size_t n) {
    return static_cast<std::uint32_t>(i + S < n ? i + S : i);
  }
};
struct LastIdx {
  static constexpr std::uint32_t get(std::size_t, std::size_t n) {
    return static_cast<std::uint32_t>(n - 1);
  }
};
struct FirstIdx {
  static constexpr std::uint32_t get(std::size_t, std::size_t) { return 0; }
};

template <class G, class A>
batch<std::uint32_t, A> permute(const batch<std::uint32_t, A>& x) {
  return xsimd::swizzle(x, xsimd::make_batch_constant<batch<std::uint32_t, A>, G>());
}

// In-register min-plus scan (Hillis-Steele): after the step of size s, lane i
// holds min over j in (i - 2s, i] of key[j] + (i - j) * step. Lanes with no
// partner at distance s compare with themselves plus s steps, which never wins.
// Up/Down are ShiftUpIdx (forward pass, j <= i) or ShiftDownIdx (backward).
template <template <std::size_t> class Shift, class A>
batch<std::uint32_t, A> min_plus_scan(batch<std::uint32_t, A> x, std::uint32_t step) {
  constexpr std::size_t lanes = batch<std::uint32_t, A>::size;
  static_assert(lanes >= 2 && lanes <= 8, "scan written for 2 .. 8 key lanes");
  x = escape::min_key(x, permute<Shift<1>>(x) + batch<std::uint32_t, A>(step));
  if constexpr (lanes > 2)
    x = escape::min_key(x, permute<Shift<2>>(x) + batch<std::uint32_t, A>(2 * step));
  if constexpr (lanes > 4)
    x = escape::min_key(x, permute<Shift<4>>(x) + batch<std::uint32_t, A>(4 * step));
  return x;
}

}  // namespace detail

// ---------------------------------------------------------------- cost kernels

template <class Arch>
void AccumulateAbsDiffU16<Arch>::call(const std::uint8_t* right_rev, std::uint8_t left,
                                      std::uint8_t trunc, int n, std::uint16_t* acc) {
  using b8 = xsimd::batch<std::uint8_t, Arch>;
  using b16 = xsimd::batch<std::uint16_t, Arch>;
  constexpr int half = static_cast<int>(b16::size);
  const b8 vleft(left);
  const b8 vtrunc(trunc);
  detail::for_blocks<static_cast<int>(b8::size)>(
      right_rev, n, acc, [&](const std::uint8_t* r, std::uint16_t* a) {
        b16 lo, hi;
        escape::widen(detail::truncated_abs_diff(vleft, b8::load_unaligned(r), vtrunc), lo, hi);
        // Wrapping add: the pipeline guarantees window * trunc <= 65535.
        (b16::load_unaligned(a) + lo).store_unaligned(a);
        (b16::load_unaligned(a + half) + hi).store_unaligned(a + half);
      },
      detail::narrower_or_null<AccumulateAbsDiffU16, Arch>([&](auto f, auto r, auto a, int m) {
        f(r, left, trunc, m, a);
      }));
}

template <class Arch>
void AccumulateAbsDiffWeightedU32<Arch>::call(const std::uint8_t* right_rev, std::uint8_t left,
                                              std::uint16_t weight, std::uint8_t trunc, int n,
                                              std::uint32_t* acc) {
  // weight * 255 must fit the 16-bit product; the model's weights are <= 255.
  constexpr std::uint16_t kMaxWeight16 = 0xffff / 0xff;  // 257
  if (weight > kMaxWeight16) {
    accumulate_abs_diff_weighted_u32_scalar(right_rev, left, weight, trunc, n, acc);
    return;
  }
  using b8 = xsimd::batch<std::uint8_t, Arch>;
  using b16 = xsimd::batch<std::uint16_t, Arch>;
  using b32 = xsimd::batch<std::uint32_t, Arch>;
  constexpr int quarter = static_cast<int>(b32::size);
  const b8 vleft(left);
  const b8 vtrunc(trunc);
  const b16 vweight(weight);
  detail::for_blocks<static_cast<int>(b8::size)>(
      right_rev, n, acc, [&](const std::uint8_t* r, std::uint32_t* a) {
        b16 d16[2];
        escape::widen(detail::truncated_abs_diff(vleft, b8::load_unaligned(r), vtrunc), d16[0],
                      d16[1]);
        for (int h = 0; h < 2; ++h) {
          b32 lo, hi;
          escape::widen(escape::mullo_u16(d16[h], vweight), lo, hi);
          std::uint32_t* out = a + 2 * h * quarter;
          (b32::load_unaligned(out) + lo).store_unaligned(out);
          (b32::load_unaligned(out + quarter) + hi).store_unaligned(out + quarter);
        }
      },
      detail::narrower_or_null<AccumulateAbsDiffWeightedU32, Arch>(
          [&](auto f, auto r, auto a, int m) { f(r, left, weight, trunc, m, a); }));
}

// ---------------------------------------------------------------- window kernels
//
// One call per sample: for each block of one u8 register of disparities, the
// block's sums live in registers while all `count` window pixels are added,
// and are stored once. Blocks: full ones from k = 0, then (n not a multiple)
// one last block ending at n, overlapping the previous one; the window kernels
// overwrite `sum`, so the shared lanes are simply written twice with the same
// value. n below one register goes to the narrower twin (AVX2 -> SSE2) or,
// at the narrowest, runs the same block on per-pixel zero-padded copies.

namespace detail {

// NB adjacent blocks of one u8 register each (out[0 .. NB * lanes)) of the box
// window sum; load(i, b) gives block b's right values of window pixel i. Two
// blocks per pass share each pixel's pointer load and broadcast.
template <int NB, class Arch, class Load>
void window_box_blocks(Load load, const std::uint8_t* left, int count,
                       const batch<std::uint8_t, Arch>& vtrunc, int group, std::uint16_t* out) {
  using b8 = batch<std::uint8_t, Arch>;
  using b16 = batch<std::uint16_t, Arch>;
  constexpr int half = static_cast<int>(b16::size);
  // Sums of widen_unordered halves; the order is restored once at the store.
  b16 lo[NB], hi[NB];
  for (int b = 0; b < NB; ++b) lo[b] = hi[b] = b16(std::uint16_t{0});
  int i = 0;
  while (i < count) {
    const int end = count - i < group ? count : i + group;
    b8 part[NB];
    const b8 first(left[i]);
    for (int b = 0; b < NB; ++b) part[b] = truncated_abs_diff(first, load(i, b), vtrunc);
    for (++i; i < end; ++i) {
      const b8 l(left[i]);
      for (int b = 0; b < NB; ++b) part[b] += truncated_abs_diff(l, load(i, b), vtrunc);
    }
    for (int b = 0; b < NB; ++b) {
      b16 plo, phi;
      escape::widen_unordered(part[b], plo, phi);
      lo[b] += plo;
      hi[b] += phi;
    }
  }
  for (int b = 0; b < NB; ++b) {
    escape::restore_widened_order(lo[b], hi[b]);
    lo[b].store_unaligned(out + 2 * b * half);
    hi[b].store_unaligned(out + (2 * b + 1) * half);
  }
}

}  // namespace detail

template <class Arch>
void AggregateWindowBoxU16<Arch>::call(const std::uint8_t* const* right_rev,
                                       const std::uint8_t* left, int count, std::uint8_t trunc,
                                       int n, std::uint16_t* sum) {
  using b8 = xsimd::batch<std::uint8_t, Arch>;
  constexpr int lanes = static_cast<int>(b8::size);
  using Half = typename detail::Narrower<Arch>::type;
  if constexpr (!std::is_void<Half>::value) {
    if (n < lanes) return AggregateWindowBoxU16<Half>::call(right_rev, left, count, trunc, n, sum);
  }
  const b8 vtrunc(trunc);
  // Up to `group` truncated differences (each <= trunc) add up in u8 lanes
  // without wrapping; only each group's partial sum is widened into the u16
  // sums. With the default T_c = 30 that is one widening per 8 pixels.
  const int group = 255 / trunc;
  if (n < lanes) {  // narrowest arch only: one block on per-pixel padded copies
    alignas(64) std::uint8_t row_pad[lanes] = {};
    alignas(64) std::uint16_t out_pad[lanes];
    const auto un = static_cast<std::size_t>(n);
    auto load = [&](int i, int) {
      std::memcpy(row_pad, right_rev[i], un);
      return b8::load_aligned(row_pad);
    };
    detail::window_box_blocks<1, Arch>(load, left, count, vtrunc, group, out_pad);
    std::memcpy(sum, out_pad, un * sizeof(std::uint16_t));
    return;
  }
  auto at = [right_rev](int k) {
    return [right_rev, k](int i, int b) { return b8::load_unaligned(right_rev[i] + k + b * lanes); };
  };
  int k = 0;
  for (; k + 2 * lanes <= n; k += 2 * lanes)
    detail::window_box_blocks<2, Arch>(at(k), left, count, vtrunc, group, sum + k);
  if (k + lanes <= n) {
    detail::window_box_blocks<1, Arch>(at(k), left, count, vtrunc, group, sum + k);
    k += lanes;
  }
  if (k < n) detail::window_box_blocks<1, Arch>(at(n - lanes), left, count, vtrunc, group, sum + n - lanes);
}

template <class Arch>
void AggregateWindowWeightedU32<Arch>::call(const std::uint8_t* const* right_rev,
                                            const std::uint8_t* left, const std::uint16_t* weight,
                                            int count, std::uint8_t trunc, int n,
                                            std::uint32_t* sum) {
  // weight * 255 must fit the 16-bit product; the model's weights are <= 255.
  constexpr std::uint16_t kMaxWeight16 = 0xffff / 0xff;  // 257
  for (int i = 0; i < count; ++i) {
    if (weight[i] > kMaxWeight16)
      return aggregate_window_weighted_u32_scalar(right_rev, left, weight, count, trunc, n, sum);
  }
  using b8 = xsimd::batch<std::uint8_t, Arch>;
  using b16 = xsimd::batch<std::uint16_t, Arch>;
  using b32 = xsimd::batch<std::uint32_t, Arch>;
  constexpr int lanes = static_cast<int>(b8::size);
  constexpr int quarter = static_cast<int>(b32::size);
  using Half = typename detail::Narrower<Arch>::type;
  if constexpr (!std::is_void<Half>::value) {
    if (n < lanes)
      return AggregateWindowWeightedU32<Half>::call(right_rev, left, weight, count, trunc, n, sum);
  }
  const b8 vtrunc(trunc);
  // acc[2h], acc[2h + 1]: the u32 sums of u16 half h (disparities
  // 2h * quarter .. 2h * quarter + 2 quarter - 1), as widen_unordered pairs.
  auto block = [&](auto load_row, std::uint32_t* out) {
    b32 acc[4] = {b32(0u), b32(0u), b32(0u), b32(0u)};
    for (int i = 0; i < count; ++i) {
      b16 d16[2];
      escape::widen(detail::truncated_abs_diff(b8(left[i]), load_row(i), vtrunc), d16[0], d16[1]);
      const b16 w(weight[i]);
      for (int h = 0; h < 2; ++h) {
        b32 lo, hi;
        escape::widen_unordered(escape::mullo_u16(d16[h], w), lo, hi);
        acc[2 * h] += lo;
        acc[2 * h + 1] += hi;
      }
    }
    for (int h = 0; h < 2; ++h) {
      escape::restore_widened_order(acc[2 * h], acc[2 * h + 1]);
      acc[2 * h].store_unaligned(out + 2 * h * quarter);
      acc[2 * h + 1].store_unaligned(out + (2 * h + 1) * quarter);
    }
  };
  if (n < lanes) {  // narrowest arch only
    alignas(64) std::uint8_t row_pad[lanes] = {};
    alignas(64) std::uint32_t out_pad[lanes];
    const auto un = static_cast<std::size_t>(n);
    block([&](int i) {
      std::memcpy(row_pad, right_rev[i], un);
      return b8::load_aligned(row_pad);
    }, out_pad);
    std::memcpy(sum, out_pad, un * sizeof(std::uint32_t));
    return;
  }
  auto run_at = [&](int k) {
    block([right_rev, k](int i) { return b8::load_unaligned(right_rev[i] + k); }, sum + k);
  };
  int k = 0;
  for (; k + lanes <= n; k += lanes) run_at(k);
  if (k < n) run_at(n - lanes);
}

namespace detail {
// The Q32 normalisation of u16 sums (one limb): col1 = hi(s*i0) + lo(s*i1) +
// half, col2 = hi(s*i1) + lo(s*i2).
template <class Arch>
struct NormalizeQ32U16 {
  using b16 = xsimd::batch<std::uint16_t, Arch>;
  b16 i0, i1, i2, low, half;
  explicit NormalizeQ32U16(std::uint64_t inv_q32)
      : i0(static_cast<std::uint16_t>(inv_q32)),
        i1(static_cast<std::uint16_t>(inv_q32 >> kLimbBits)),
        i2(static_cast<std::uint16_t>(inv_q32 >> (2 * kLimbBits))),
        low(static_cast<std::uint16_t>(kColumnLow)),
        half(static_cast<std::uint16_t>(kColumnHalf)) {}
  b16 operator()(const b16& s) const {
    const b16 a = escape::mulhi_u16(s, i0);
    const b16 b = escape::mullo_u16(s, i1);
    const b16 col2 = escape::mulhi_u16(s, i1) + escape::mullo_u16(s, i2);
    // col1 = a + b + half can reach 2^17: shift the parts separately and
    // carry the sum of their low 12 bits.
    const b16 col1_shifted =
        (a >> kColumnShift) + (b >> kColumnShift) + (((a & low) + (b & low) + half) >> kColumnShift);
    return col1_shifted + (col2 << kCol2Shift);
  }
};
}  // namespace detail

template <class Arch>
void NormalizeCostsU16<Arch>::call(const std::uint16_t* sum, std::uint64_t inv_q32, int n,
                                   std::uint16_t* cost_q4) {
  using b16 = xsimd::batch<std::uint16_t, Arch>;
  const detail::NormalizeQ32U16<Arch> normalize(inv_q32);
  detail::for_output_blocks<static_cast<int>(b16::size)>(
      sum, n, cost_q4,
      [&](const std::uint16_t* s_ptr, std::uint16_t* c_ptr) {
        normalize(b16::load_unaligned(s_ptr)).store_unaligned(c_ptr);
      },
      detail::narrower_or_null<NormalizeCostsU16, Arch>(
          [&](auto f, auto s_ptr, auto c_ptr, int m) { f(s_ptr, inv_q32, m, c_ptr); }));
}

// Byte sums widened to u16 lanes, then as NormalizeCostsU16. A run shorter
// than a byte register goes through u16 copies to NormalizeCostsU16.
template <class Arch>
void NormalizeCostsU8<Arch>::call(const std::uint8_t* sum, std::uint64_t inv_q32, int n, std::uint16_t* cost_q4) {
  using b8 = xsimd::batch<std::uint8_t, Arch>;
  using b16 = xsimd::batch<std::uint16_t, Arch>;
  constexpr int lanes = static_cast<int>(b8::size);
  if (n < lanes) {
    std::uint16_t wide[lanes];
    for (int k = 0; k < n; ++k) wide[k] = sum[k];
    NormalizeCostsU16<Arch>::call(wide, inv_q32, n, cost_q4);
    return;
  }
  const detail::NormalizeQ32U16<Arch> normalize(inv_q32);
  const auto block = [&](int k) {
    b16 lo, hi;
    escape::widen(b8::load_unaligned(sum + k), lo, hi);
    normalize(lo).store_unaligned(cost_q4 + k);
    normalize(hi).store_unaligned(cost_q4 + k + lanes / 2);
  };
  int k = 0;
  for (; k + lanes <= n; k += lanes) block(k);
  if (k < n) block(n - lanes);  // the full block ending at n
}

template <class Arch>
void NormalizeCostsU32<Arch>::call(const std::uint32_t* sum, std::uint64_t inv_q32, int n,
                                   std::uint16_t* cost_q4) {
  using b16 = xsimd::batch<std::uint16_t, Arch>;
  using b32 = xsimd::batch<std::uint32_t, Arch>;
  constexpr int quarter = static_cast<int>(b32::size);
  const b16 i0(static_cast<std::uint16_t>(inv_q32));
  const b16 i1(static_cast<std::uint16_t>(inv_q32 >> detail::kLimbBits));
  const b16 i2(static_cast<std::uint16_t>(inv_q32 >> (2 * detail::kLimbBits)));
  const b32 mask(detail::kLimbMask);
  const b32 half(detail::kColumnHalf);
  // Viewed as u16 lanes, each sum is (s0, s1); one 16-bit multiply by an inv
  // limb gives both s0*i and s1*i, one column apart, in the low and high halves
  // of the same u32 lane. Columns are summed in u32 lanes, so nothing overflows.
  auto costs = [&](const b32& s) {
    const b16 v = xsimd::bitwise_cast<b16>(s);
    const b32 lo0 = xsimd::bitwise_cast<b32>(escape::mullo_u16(v, i0));
    const b32 hi0 = xsimd::bitwise_cast<b32>(escape::mulhi_u16(v, i0));
    const b32 lo1 = xsimd::bitwise_cast<b32>(escape::mullo_u16(v, i1));
    const b32 hi1 = xsimd::bitwise_cast<b32>(escape::mulhi_u16(v, i1));
    const b32 lo2 = xsimd::bitwise_cast<b32>(escape::mullo_u16(v, i2));
    const b32 col1 = (hi0 & mask) + (lo1 & mask) + (lo0 >> detail::kLimbBits) + half;
    const b32 col2 = (hi1 & mask) + (hi0 >> detail::kLimbBits) + (lo1 >> detail::kLimbBits) +
                     (lo2 & mask);
    return (col1 >> detail::kColumnShift) + (col2 << detail::kCol2Shift);
  };
  detail::for_output_blocks<static_cast<int>(b16::size)>(
      sum, n, cost_q4, [&](const std::uint32_t* s_ptr, std::uint16_t* c_ptr) {
        escape::narrow_u32(costs(b32::load_unaligned(s_ptr)),
                           costs(b32::load_unaligned(s_ptr + quarter)))
            .store_unaligned(c_ptr);
      },
      detail::narrower_or_null<NormalizeCostsU32, Arch>(
          [&](auto f, auto s_ptr, auto c_ptr, int m) { f(s_ptr, inv_q32, m, c_ptr); }));
}

// ---------------------------------------------------------------- DP step

// Same packed-key algorithm as dp_step_scalar, vectorised:
//   forward:  f[k] = min(own[k], f[k-1] + step): a min-plus scan inside each
//             batch, then min with (carry + (i+1) * step), carry = f of the
//             previous batch's last lane;
//   backward: b[k] = min(f[k], b[k+1] + step), the mirror image, batches from
//             the end, carry = b of the next batch's first lane;
//   final:    out = cost + (b >> 8) - min g, ptr = b & 0xff, in chunks of one
//             u8 register (4 key batches) so the indices narrow in registers.
// min over keys is associative, so the scan gives the same keys as the serial
// loop; lanes past n hold kPadKey-based keys and cannot change lanes below n
// (any path through them is longer, and their g is >= g[n-1]).
template <class Arch>
void DpStep<Arch>::call(const std::uint16_t* cost_q4, const std::uint32_t* prev,
                        std::uint32_t penalty, int n, std::uint32_t* out, std::uint8_t* ptr) {
  using bk = xsimd::batch<std::uint32_t, Arch>;
  using b16 = xsimd::batch<std::uint16_t, Arch>;
  using b8 = xsimd::batch<std::uint8_t, Arch>;
  constexpr int lanes = static_cast<int>(bk::size);
  constexpr int chunk = static_cast<int>(b8::size);  // = 4 * lanes
  using Half = typename detail::Narrower<Arch>::type;
  if constexpr (!std::is_void<Half>::value) {
    // One narrower final chunk covers the row: the wide passes would be mostly padding.
    if (n <= chunk / 2) return DpStep<Half>::call(cost_q4, prev, penalty, n, out, ptr);
  }
  alignas(64) std::uint32_t keys[detail::kMaxLanes + chunk];

  const std::uint32_t step = penalty << detail::kIndexBits;
  const int batches = (n + lanes - 1) / lanes;
  const int chunks = (n + chunk - 1) / chunk;

  alignas(64) std::uint32_t lane_tmp[lanes];
  for (int i = 0; i < lanes; ++i) lane_tmp[i] = static_cast<std::uint32_t>(i);
  const bk iota = bk::load_aligned(lane_tmp);
  for (int i = 0; i < lanes; ++i) lane_tmp[i] = static_cast<std::uint32_t>(i + 1) * step;
  const bk ramp_up = bk::load_aligned(lane_tmp);
  for (int i = 0; i < lanes; ++i) lane_tmp[i] = static_cast<std::uint32_t>(lanes - i) * step;
  const bk ramp_down = bk::load_aligned(lane_tmp);

  // Forward pass.
  bk carry(detail::kPadKey);
  for (int b = 0; b < batches; ++b) {
    const int k = b * lanes;
    bk values;
    if (k + lanes <= n) {
      values = bk::load_unaligned(prev + k);
    } else {
      for (int i = 0; i < lanes; ++i) lane_tmp[i] = detail::kPadKey >> detail::kIndexBits;
      std::memcpy(lane_tmp, prev + k, static_cast<std::size_t>(n - k) * sizeof(std::uint32_t));
      values = bk::load_aligned(lane_tmp);
    }
    bk x = (values << detail::kIndexBits) | (iota + bk(static_cast<std::uint32_t>(k)));
    x = detail::min_plus_scan<detail::ShiftUpIdx>(x, step);
    x = escape::min_key(x, carry + ramp_up);
    x.store_aligned(keys + k);
    carry = detail::permute<detail::LastIdx>(x);
  }

  // Backward pass, tracking the smallest key (its value is min g).
  carry = bk(detail::kPadKey);
  bk smallest(detail::kPadKey);
  for (int b = batches - 1; b >= 0; --b) {
    const int k = b * lanes;
    bk x = detail::min_plus_scan<detail::ShiftDownIdx>(bk::load_aligned(keys + k), step);
    x = escape::min_key(x, carry + ramp_down);
    x.store_aligned(keys + k);
    carry = detail::permute<detail::FirstIdx>(x);
    smallest = escape::min_key(smallest, x);
  }
  smallest.store_aligned(lane_tmp);
  std::uint32_t min_key = lane_tmp[0];
  for (int i = 1; i < lanes; ++i) min_key = lane_tmp[i] < min_key ? lane_tmp[i] : min_key;
  const bk min_g(min_key >> detail::kIndexBits);

  // Final pass. Keys past the last batch are defined (zero) but discarded.
  for (int k = batches * lanes; k < chunks * chunk; ++k) keys[k] = 0;
  auto finish = [&](const std::uint32_t* key, const std::uint16_t* cost, std::uint32_t* o,
                    std::uint8_t* p) {
    bk c32[4];
    escape::widen(b16::load_unaligned(cost), c32[0], c32[1]);
    escape::widen(b16::load_unaligned(cost + 2 * lanes), c32[2], c32[3]);
    bk kk[4];
    for (int j = 0; j < 4; ++j) {
      kk[j] = bk::load_aligned(key + j * lanes);
      (c32[j] + (kk[j] >> detail::kIndexBits) - min_g).store_unaligned(o + j * lanes);
    }
    escape::narrow_u16(escape::narrow_u32(kk[0], kk[1]), escape::narrow_u32(kk[2], kk[3]))
        .store_unaligned(p);
  };
  for (int c = 0; c < chunks; ++c) {
    const int k = c * chunk;
    if (k + chunk <= n) {
      finish(keys + k, cost_q4 + k, out + k, ptr + k);
    } else {
      const std::size_t m = static_cast<std::size_t>(n - k);
      alignas(64) std::uint16_t cost_pad[chunk] = {};
      alignas(64) std::uint32_t out_pad[chunk];
      alignas(64) std::uint8_t ptr_pad[chunk];
      std::memcpy(cost_pad, cost_q4 + k, m * sizeof(std::uint16_t));
      finish(keys + k, cost_pad, out_pad, ptr_pad);
      std::memcpy(out + k, out_pad, m * sizeof(std::uint32_t));
      std::memcpy(ptr + k, ptr_pad, m);
    }
  }
}

// ---------------------------------------------------------------- u16 DP
//
// Values only (no packed index): g = min(forward scan, backward scan) of prev,
// both scans computed from prev and independent of each other. Each is an
// in-register min-plus scan on u16 lanes (steps 1, 2, 4 [, 8] lanes, shifted-in
// lanes are 0xFFFF) plus a carry between batches. Adds saturate: every true g[k]
// is <= prev[k] <= 0xFFFF, so a sum clamped at 0xFFFF loses a min it would have
// lost (or tied in value) anyway, and the result is exact for any penalty.
// min g = min prev (g[k] <= prev[k], and every g >= min prev), so the minimum is
// known after the forward pass and the backward pass writes the output directly.

namespace detail {

constexpr std::uint16_t kU16Max = 0xFFFF;

// Lane-count constants for u16 batches of up to kCountLanes lanes:
// kCount[i] = i, kCountDown[i] = kCountLanes - i.
constexpr int kCountLanes = 32;
alignas(64) constexpr std::uint16_t kCount[kCountLanes + 1] = {
    0,  1,  2,  3,  4,  5,  6,  7,  8,  9,  10, 11, 12, 13, 14, 15, 16,
    17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27, 28, 29, 30, 31, 32};
alignas(64) constexpr std::uint16_t kCountDown[kCountLanes] = {
    32, 31, 30, 29, 28, 27, 26, 25, 24, 23, 22, 21, 20, 19, 18, 17,
    16, 15, 14, 13, 12, 11, 10, 9,  8,  7,  6,  5,  4,  3,  2,  1};
// kAround[kAroundCentre + i] = 0xFFFF for |i| <= 1, else 0: loaded at
// kAroundCentre - k + j, lane l is all ones exactly when |j + l - k| <= 1
// (0 <= k < 256, 0 <= j < 256, up to 32 lanes).
constexpr int kAroundCentre = 256;
struct AroundTable {
  alignas(64) std::uint16_t v[2 * kAroundCentre + kCountLanes] = {};
  constexpr AroundTable() {
    v[kAroundCentre - 1] = v[kAroundCentre] = v[kAroundCentre + 1] = 0xFFFF;
  }
};
constexpr AroundTable kAround{};
// Largest penalty whose ramp (up to 16 steps) fits u16 without saturating.
constexpr std::uint32_t kMaxRampPenalty = 0xFFFF / 16;

// Internal linkage: each arch object keeps its own copy (see escape_ops.hpp).
static inline std::uint16_t saturate_u16(std::uint64_t v) {
  return static_cast<std::uint16_t>(v < kU16Max ? v : kU16Max);
}

template <bool Up, std::size_t S, class A>
batch<std::uint16_t, A> shifted_u16(const batch<std::uint16_t, A>& x) {
  if constexpr (Up) {
    return escape::shift_up_u16<S>(x);
  } else {
    return escape::shift_down_u16<S>(x);
  }
}

// step[t] = min(2^t penalty, 0xFFFF). Up: lane i ends as min_{j <= i in batch}
// x[j] + (i - j) penalty; down: the mirror image (j >= i).
template <bool Up, class A>
batch<std::uint16_t, A> min_plus_scan_u16(batch<std::uint16_t, A> x,
                                          const batch<std::uint16_t, A> (&step)[4]) {
  constexpr std::size_t lanes = batch<std::uint16_t, A>::size;
  static_assert(lanes == 8 || lanes == 16, "u16 scan written for 8 or 16 lanes");
  x = escape::min_u16(x, xsimd::sadd(shifted_u16<Up, 1>(x), step[0]));
  x = escape::min_u16(x, xsimd::sadd(shifted_u16<Up, 2>(x), step[1]));
  x = escape::min_u16(x, xsimd::sadd(shifted_u16<Up, 4>(x), step[2]));
  if constexpr (lanes > 8) x = escape::min_u16(x, xsimd::sadd(shifted_u16<Up, 8>(x), step[3]));
  return x;
}

// prev split into full batches read in place and one 0xFFFF-padded tail batch
// (0xFFFF never wins a min and never lowers min prev below a real lane's).
template <class A>
struct PaddedU16 {
  static constexpr int lanes = static_cast<int>(batch<std::uint16_t, A>::size);
  const std::uint16_t* data;
  int full;     // batches wholly inside [0, n)
  int batches;  // full + (tail > 0)
  int tail;     // n - full * lanes
  alignas(64) std::uint16_t pad[lanes];
  PaddedU16(const std::uint16_t* p, int n)
      : data(p), full(n / lanes), batches((n + lanes - 1) / lanes), tail(n - full * lanes) {
    for (int i = 0; i < lanes; ++i) pad[i] = kU16Max;  // always: one store, and no read of an unset pad
    if (tail > 0) std::memcpy(pad, p + full * lanes, static_cast<std::size_t>(tail) * sizeof(std::uint16_t));
  }
  batch<std::uint16_t, A> load(int b) const {
    return b < full ? batch<std::uint16_t, A>::load_unaligned(data + b * lanes)
                    : batch<std::uint16_t, A>::load_aligned(pad);
  }
};

}  // namespace detail

template <class Arch>
void DpStepU16<Arch>::call(const std::uint16_t* cost_q4, const std::uint16_t* prev,
                           std::uint32_t penalty, int n, std::uint16_t* out) {
  using b16 = xsimd::batch<std::uint16_t, Arch>;
  constexpr int lanes = static_cast<int>(b16::size);

  b16 step[4];
  for (int t = 0; t < 4; ++t) step[t] = b16(detail::saturate_u16(std::uint64_t{penalty} << t));
  alignas(64) std::uint16_t lane_tmp[lanes];
  // ramp_up[i] = min((i + 1) p, 0xFFFF), ramp_down[i] = min((lanes - i) p, 0xFFFF).
  b16 ramp_up, ramp_down;
  if (penalty <= detail::kMaxRampPenalty) {  // no lane saturates: one multiply each
    const b16 vp(static_cast<std::uint16_t>(penalty));
    ramp_up = escape::mullo_u16(b16::load_unaligned(detail::kCount + 1), vp);
    ramp_down = escape::mullo_u16(b16::load_unaligned(detail::kCountDown + detail::kCountLanes - lanes), vp);
  } else {
    for (int i = 0; i < lanes; ++i)
      lane_tmp[i] = detail::saturate_u16(std::uint64_t{penalty} * static_cast<std::uint64_t>(i + 1));
    ramp_up = b16::load_aligned(lane_tmp);
    for (int i = 0; i < lanes; ++i)
      lane_tmp[i] = detail::saturate_u16(std::uint64_t{penalty} * static_cast<std::uint64_t>(lanes - i));
    ramp_down = b16::load_aligned(lane_tmp);
  }

  // Forward scan (j <= k) into fwd, and min prev on the way.
  alignas(64) std::uint16_t fwd[detail::kMaxLanes + lanes];
  b16 carry(detail::kU16Max);
  b16 low(detail::kU16Max);
  if (n >= lanes && n % lanes != 0) {
    // The last block is the full block ending at n, overlapping the one
    // before: its scans start from the scans' values just outside it (the
    // forward value at n - lanes - 1, the backward one at the end of the
    // range), so every lane gets the exact value the other block gives it
    // too (the scans are exact, see above), and the output's overlapping
    // lanes are written twice with the same value. No padded copies.
    const int full = n / lanes, tail = n - lanes;
    for (int b = 0; b < full; ++b) {
      b16 x = b16::load_unaligned(prev + b * lanes);
      low = escape::min_u16(low, x);
      x = detail::min_plus_scan_u16<true>(x, step);
      x = escape::min_u16(x, xsimd::sadd(carry, ramp_up));
      x.store_aligned(fwd + b * lanes);
      carry = escape::broadcast_last_u16(x);
    }
    const b16 x_tail = b16::load_unaligned(prev + tail);
    low = escape::min_u16(low, x_tail);
    const b16 fwd_tail = escape::min_u16(detail::min_plus_scan_u16<true>(x_tail, step),
                                         xsimd::sadd(b16(fwd[tail - 1]), ramp_up));
    const b16 min_g(escape::hmin_u16(low));
    b16 y = detail::min_plus_scan_u16<false>(x_tail, step);  // nothing after n
    (b16::load_unaligned(cost_q4 + tail) + escape::min_u16(y, fwd_tail) - min_g).store_unaligned(out + tail);
    // The backward value just after block full - 1, from the tail's lanes.
    alignas(64) std::uint16_t y_tail[lanes];
    y.store_aligned(y_tail);
    carry = b16(y_tail[full * lanes - tail]);
    for (int b = full - 1; b >= 0; --b) {
      y = detail::min_plus_scan_u16<false>(b16::load_unaligned(prev + b * lanes), step);
      y = escape::min_u16(y, xsimd::sadd(carry, ramp_down));
      carry = escape::broadcast_first_u16(y);
      const b16 g = escape::min_u16(y, b16::load_aligned(fwd + b * lanes));
      (b16::load_unaligned(cost_q4 + b * lanes) + g - min_g).store_unaligned(out + b * lanes);
    }
    return;
  }
  const detail::PaddedU16<Arch> in(prev, n);
  for (int b = 0; b < in.batches; ++b) {
    b16 x = in.load(b);
    low = escape::min_u16(low, x);
    x = detail::min_plus_scan_u16<true>(x, step);
    x = escape::min_u16(x, xsimd::sadd(carry, ramp_up));
    x.store_aligned(fwd + b * lanes);
    carry = escape::broadcast_last_u16(x);
  }
  const b16 min_g(escape::hmin_u16(low));

  // Backward scan (j >= k), g = min of both, out = cost + g - min g (wraps
  // mod 2^16 like the scalar kernel if the caller's bound is exceeded).
  carry = b16(detail::kU16Max);
  for (int b = in.batches - 1; b >= 0; --b) {
    b16 y = detail::min_plus_scan_u16<false>(in.load(b), step);
    y = escape::min_u16(y, xsimd::sadd(carry, ramp_down));
    carry = escape::broadcast_first_u16(y);
    const b16 g = escape::min_u16(y, b16::load_aligned(fwd + b * lanes));
    const int k = b * lanes;
    if (b < in.full) {
      (b16::load_unaligned(cost_q4 + k) + g - min_g).store_unaligned(out + k);
    } else {
      const std::size_t m = static_cast<std::size_t>(in.tail);
      alignas(64) std::uint16_t cost_pad[lanes] = {};
      std::memcpy(cost_pad, cost_q4 + k, m * sizeof(std::uint16_t));
      (b16::load_aligned(cost_pad) + g - min_g).store_aligned(lane_tmp);
      std::memcpy(out + k, lane_tmp, m * sizeof(std::uint16_t));
    }
  }
}

// Every term prev[j] + penalty |k - j| in u16 lanes (product <= 255 * 257 fits;
// the sum saturates), their minimum, then the first lane equal to it. A
// saturated term reads 0xFFFF and could only tie with a minimum of 0xFFFF:
// that case, and penalties above 257, go to the scalar kernel. Then the
// smallest j whose term equals the minimum, by a second min over indices.
template <class Arch>
int DpPointerU16<Arch>::call(const std::uint16_t* prev, std::uint32_t penalty, int n, int k) {
  constexpr std::uint32_t kMaxPenalty16 = 0xffff / 0xff;  // 257
  if (penalty > kMaxPenalty16) return dp_pointer_u16_scalar(prev, penalty, n, k);
  using b16 = xsimd::batch<std::uint16_t, Arch>;
  constexpr int lanes = static_cast<int>(b16::size);
  const b16 iota = b16::load_aligned(detail::kCount);
  const b16 vk(static_cast<std::uint16_t>(k));
  const b16 vp(static_cast<std::uint16_t>(penalty));
  // When n is at least one batch but not a multiple, the last batch is the
  // full one ending at n (a term seen twice changes neither the min nor its
  // first index); otherwise it is a padded copy (pad lanes hold 0xFFFF terms,
  // never the min).
  const bool overlap = n >= lanes && n % lanes != 0;
  const detail::PaddedU16<Arch> in(prev, overlap ? n / lanes * lanes : n);
  const int batches = overlap ? n / lanes + 1 : in.batches;
  const int last_start = overlap ? n - lanes : (batches - 1) * lanes;
  alignas(64) std::uint16_t terms[detail::kMaxLanes + lanes];
  b16 low(detail::kU16Max);
  const auto terms_of = [&](int b, int at, const b16& p) {
    const b16 j = iota + b16(static_cast<std::uint16_t>(at));
    const b16 dist = xsimd::ssub(j, vk) | xsimd::ssub(vk, j);
    const b16 t = xsimd::sadd(p, escape::mullo_u16(dist, vp));
    t.store_aligned(terms + b * lanes);
    low = escape::min_u16(low, t);
  };
  for (int b = 0; b + 1 < batches; ++b) terms_of(b, b * lanes, in.load(b));
  terms_of(batches - 1, last_start, overlap ? b16::load_unaligned(prev + last_start) : in.load(batches - 1));
  const std::uint16_t m = escape::hmin_u16(low);
  if (m == detail::kU16Max) return dp_pointer_u16_scalar(prev, penalty, n, k);
  // Smallest index whose term equals m, without branches: min over
  // (term == m ? j : 0xFFFF).
  const b16 vm(m);
  const b16 none(detail::kU16Max);
  b16 first(detail::kU16Max);
  const auto first_of = [&](int b, int at) {
    const b16 j = iota + b16(static_cast<std::uint16_t>(at));
    first = escape::min_u16(first, xsimd::select(b16::load_aligned(terms + b * lanes) == vm, j, none));
  };
  for (int b = 0; b + 1 < batches; ++b) first_of(b, b * lanes);
  first_of(batches - 1, last_start);
  return escape::hmin_u16(first);
}


// ------------------------------------------------------------------ census
// Pixels are compared as int8 lanes with the top bit flipped (unsigned order
// as signed order), where every target has a native signed compare; each
// neighbour shifts its bit into its plane's byte, one lane per pixel. The
// width's last partial block is redone as the full block ending at the last
// pixel (same values written twice) when the row is at least a block wide,
// else the row goes to the scalar twin.
template <class Arch>
void CensusRowU8<Arch>::call(const std::uint8_t* const* rows, int win_w, int win_h, int width,
                             std::uint8_t* const* planes) {
  using b8 = xsimd::batch<std::uint8_t, Arch>;
  using bs8 = xsimd::batch<std::int8_t, Arch>;
  constexpr int lanes = static_cast<int>(b8::size);
  if (width < lanes) {
    census_row_u8_scalar(rows, win_w, win_h, width, planes);
    return;
  }
  const int rx = win_w / 2, ry = win_h / 2;
  const int bits = win_w * win_h - 1;
  // The neighbours in bit order (raster order, centre skipped): row, offset.
  const std::uint8_t* nb_row[63];
  int nb_dx[63];
  for (int dy = 0, b = 0; dy < win_h; ++dy)
    for (int dx = -rx; dx <= rx; ++dx) {
      if (dy == ry && dx == 0) continue;
      nb_row[b] = rows[dy];
      nb_dx[b] = dx;
      ++b;
    }
  const b8 flip(std::uint8_t{0x80});
  const auto biased = [&](const std::uint8_t* p) { return xsimd::bitwise_cast<bs8>(b8::load_unaligned(p) ^ flip); };
  const bs8 zero(std::int8_t{0}), one(std::int8_t{1});
  const auto block = [&](int x) {
    const bs8 centre = biased(rows[ry] + x);
    // Plane p holds bits 8p .. 8p + 7: the highest first, each step doubling
    // the byte (a shift by one) and adding the next bit.
    for (int p = 0, b0 = 0; b0 < bits; ++p, b0 += 8) {
      bs8 acc = zero;
      for (int b = std::min(bits, b0 + 8) - 1; b >= b0; --b)
        acc = acc + acc + xsimd::select(biased(nb_row[b] + x + nb_dx[b]) < centre, one, zero);
      xsimd::bitwise_cast<b8>(acc).store_unaligned(planes[p] + x);
    }
  };
  int x = 0;
  for (; x + lanes <= width; x += lanes) block(x);
  if (x < width) block(width - lanes);
}

namespace detail {
// out[k .. k + lanes) = block(k) for every block of [0, n): the full blocks,
// then, when n is at least a block, the full block ending at n (its first
// lanes rewrite the same values), else the first n lanes through a copy.
// Always inlined: census_costs_row calls it once per pixel, and as a call
// (GCC 12 did not inline it) its block read the broadcast descriptors back
// from the stack: census_pixels on Cones took 1.80 ms instead of 1.37.
// T is the lane type (u16 costs or sums, byte costs).
template <int kLanes, class T, class Block>
inline __attribute__((always_inline)) void store_blocks(int n, T* out, Block block) {
  int k = 0;
  for (; k + kLanes <= n; k += kLanes) block(k).store_unaligned(out + k);
  if (k == n) return;
  if (n >= kLanes) {
    block(n - kLanes).store_unaligned(out + n - kLanes);
  } else {
    alignas(64) T tmp[kLanes];
    block(k).store_aligned(tmp);
    std::memcpy(out + k, tmp, static_cast<std::size_t>(n - k) * sizeof(T));
  }
}
}  // namespace detail

namespace detail {
// store_blocks for u16 values made a byte block at a time: pair(k, lo, hi)
// gives values k .. k + lanes8 as two u16 registers. Same tails: the full
// block ending at n, or below a block the first n values through a copy.
template <class Arch, class Pair>
inline __attribute__((always_inline)) void store_u16_pairs(int n, std::uint16_t* out, Pair pair) {
  using b16 = xsimd::batch<std::uint16_t, Arch>;
  constexpr int lanes8 = static_cast<int>(xsimd::batch<std::uint8_t, Arch>::size), half = lanes8 / 2;
  const auto put = [&](int k, std::uint16_t* to) {
    b16 lo, hi;
    pair(k, lo, hi);
    lo.store_unaligned(to);
    hi.store_unaligned(to + half);
  };
  int k = 0;
  for (; k + lanes8 <= n; k += lanes8) put(k, out + k);
  if (k == n) return;
  if (n >= lanes8) {
    put(n - lanes8, out + n - lanes8);
  } else {
    alignas(64) std::uint16_t tmp[lanes8];
    put(k, tmp);
    std::memcpy(out + k, tmp, static_cast<std::size_t>(n - k) * sizeof(std::uint16_t));
  }
}
}  // namespace detail

// A block's sums stay in registers while the window's entries are walked:
// bytes for up to 31 entries (each counts at most 8), then widened into two
// u16 registers (in widen_unordered's order, restored once at the end).
template <class Arch>
void CensusWindowU16<Arch>::call(const std::uint8_t* const* right_rev, const std::uint8_t* left,
                                 int count, int n, std::uint16_t* sum) {
  using b8 = xsimd::batch<std::uint8_t, Arch>;
  using b16 = xsimd::batch<std::uint16_t, Arch>;
  constexpr int kEntriesPerByte = 31;
  detail::store_u16_pairs<Arch>(n, sum, [&](int k, b16& lo, b16& hi) {
    lo = b16(std::uint16_t{0});
    hi = b16(std::uint16_t{0});
    for (int i0 = 0; i0 < count; i0 += kEntriesPerByte) {
      const int i1 = std::min(count, i0 + kEntriesPerByte);
      b8 acc(std::uint8_t{0});
      for (int i = i0; i < i1; ++i) acc = acc + escape::popcount_u8(b8::load_unaligned(right_rev[i] + k) ^ b8(left[i]));
      b16 l, h;
      escape::widen_unordered(acc, l, h);
      lo = lo + l;
      hi = hi + h;
    }
    escape::restore_widened_order(lo, hi);
  });
}

namespace detail {
// A row's per-pixel Hamming costs with the plane count known: the planes' left
// descriptors stay broadcast in registers across the pixel's disparity blocks,
// and the planes' counts are added as bytes (at most 8 P <= 64). u16 costs
// widen each byte block into two registers.
template <class Arch, int P, class T>
void census_costs_row(const std::uint8_t* const* right_rev, const std::uint8_t* const* left, int width, int n,
                      std::size_t stride, T* out) {
  using b8 = xsimd::batch<std::uint8_t, Arch>;
  using b16 = xsimd::batch<std::uint16_t, Arch>;
  constexpr int lanes8 = static_cast<int>(b8::size);
  for (int x = 0; x < width; ++x) {
    b8 l[P];
    const std::uint8_t* r[P];
    for (int p = 0; p < P; ++p) {
      l[p] = b8(left[p][x]);
      r[p] = right_rev[p] - x;
    }
    T* o = out + static_cast<std::size_t>(x) * stride;
    const auto costs8 = [&](int k) {
      b8 acc = escape::popcount_u8(b8::load_unaligned(r[0] + k) ^ l[0]);
      for (int p = 1; p < P; ++p) acc = acc + escape::popcount_u8(b8::load_unaligned(r[p] + k) ^ l[p]);
      return acc;
    };
    if constexpr (sizeof(T) == 1)
      store_blocks<lanes8>(n, o, costs8);
    else
      store_u16_pairs<Arch>(n, o, [&](int k, b16& lo, b16& hi) { escape::widen(costs8(k), lo, hi); });
  }
}

template <class Arch, class T>
void census_costs_row_of_planes(const std::uint8_t* const* right_rev, const std::uint8_t* const* left,
                                int planes, int width, int n, std::size_t stride, T* out) {
  switch (planes) {
    case 1: census_costs_row<Arch, 1>(right_rev, left, width, n, stride, out); break;
    case 2: census_costs_row<Arch, 2>(right_rev, left, width, n, stride, out); break;
    case 3: census_costs_row<Arch, 3>(right_rev, left, width, n, stride, out); break;
    case 4: census_costs_row<Arch, 4>(right_rev, left, width, n, stride, out); break;
    case 5: census_costs_row<Arch, 5>(right_rev, left, width, n, stride, out); break;
    case 6: census_costs_row<Arch, 6>(right_rev, left, width, n, stride, out); break;
    case 7: census_costs_row<Arch, 7>(right_rev, left, width, n, stride, out); break;
    default: census_costs_row<Arch, 8>(right_rev, left, width, n, stride, out); break;
  }
}
}  // namespace detail

template <class Arch>
void CensusCostsRowU16<Arch>::call(const std::uint8_t* const* right_rev, const std::uint8_t* const* left,
                                   int planes, int width, int n, std::size_t stride, std::uint16_t* out) {
  detail::census_costs_row_of_planes<Arch>(right_rev, left, planes, width, n, stride, out);
}

template <class Arch>
void CensusCostsRowU8<Arch>::call(const std::uint8_t* const* right_rev, const std::uint8_t* const* left,
                                  int planes, int width, int n, std::size_t stride, std::uint8_t* out) {
  detail::census_costs_row_of_planes<Arch>(right_rev, left, planes, width, n, stride, out);
}

namespace detail {
// sum_rows on lanes of T (u16, or bytes), mod 2^(8 sizeof T): each block's sum
// stays in a register while the rows are added.
template <class Arch, class T>
void sum_rows(const T* const* rows, int count, std::size_t n, T* sum) {
  using bt = xsimd::batch<T, Arch>;
  constexpr std::size_t lanes = bt::size;
  const auto block = [&](std::size_t j) {
    bt acc = bt::load_unaligned(rows[0] + j);
    for (int i = 1; i < count; ++i) acc = acc + bt::load_unaligned(rows[i] + j);
    acc.store_unaligned(sum + j);
  };
  std::size_t j = 0;
  for (; j + lanes <= n; j += lanes) block(j);
  if (j < n && n >= lanes) {  // the full block ending at n (sum is no row)
    block(n - lanes);
    return;
  }
  for (; j < n; ++j) {
    std::uint32_t s = 0;
    for (int i = 0; i < count; ++i) s += rows[i][j];
    sum[j] = static_cast<T>(s);
  }
}
}  // namespace detail

template <class Arch>
void SumRowsU16<Arch>::call(const std::uint16_t* const* rows, int count, std::size_t n,
                            std::uint16_t* sum) {
  detail::sum_rows<Arch>(rows, count, n, sum);
}

template <class Arch>
void SumRowsU8<Arch>::call(const std::uint8_t* const* rows, int count, std::size_t n, std::uint8_t* sum) {
  detail::sum_rows<Arch>(rows, count, n, sum);
}

// ------------------------------------------------------------------ paths
namespace detail {
// PathStepsU16 for a compile-time count: each block of disparities loads C
// and S once and keeps the sum of the count outputs in a register. A partial
// last block is the full block ending at n. Its sums are read before the
// other blocks store theirs, so that its overlapping lanes add to the same old
// sums (the same results as the block before; and no load that straddles a
// store just made). out and the minima see the same values twice (out is
// neither prev nor cost).
// load_cost(k): the costs of disparities k .. k + lanes - 1 as u16 lanes.
template <class Arch, int kCount, class LoadCost>
void path_steps(const LoadCost& load_cost, const std::uint16_t* const* prev, const std::uint16_t* prev_min,
                const std::uint16_t* p1, const std::uint16_t* p2, int n, std::uint16_t* const* out,
                std::uint16_t* sum, int accumulate, std::uint16_t* mins) {
  using b16 = xsimd::batch<std::uint16_t, Arch>;
  constexpr int lanes = static_cast<int>(b16::size);
  b16 vp1[kCount], vmin_prev[kCount], jump[kCount], low[kCount];
  for (int r = 0; r < kCount; ++r) {
    vp1[r] = b16(p1[r]);
    vmin_prev[r] = b16(prev_min[r]);
    jump[r] = b16(static_cast<std::uint16_t>(std::uint32_t{prev_min[r]} + p2[r]));
    low[r] = b16(kU16Max);
  }
  const auto block = [&](int k, const b16& old) {
    const b16 c = load_cost(k);
    b16 s = old;
    for (int r = 0; r < kCount; ++r) {
      const std::uint16_t* pr = prev[r];
      b16 best = escape::min_u16(b16::load_unaligned(pr + k), xsimd::sadd(b16::load_unaligned(pr + k - 1), vp1[r]));
      best = escape::min_u16(best, xsimd::sadd(b16::load_unaligned(pr + k + 1), vp1[r]));
      best = escape::min_u16(best, jump[r]);
      const b16 v = c + best - vmin_prev[r];
      v.store_unaligned(out[r] + k);
      low[r] = escape::min_u16(low[r], v);
      s += v;
    }
    s.store_unaligned(sum + k);
  };
  const bool overlap = n % lanes != 0;
  const int tail = n - lanes;
  const b16 zero(std::uint16_t{0});
  const b16 old_tail = overlap && accumulate ? b16::load_unaligned(sum + tail) : zero;
  int k = 0;
  for (; k + lanes <= n; k += lanes) block(k, accumulate ? b16::load_unaligned(sum + k) : zero);
  if (overlap) block(tail, old_tail);
  for (int r = 0; r < kCount; ++r) mins[r] = escape::hmin_u16(low[r]);
}

// The compile-time count of paths (1 .. 4).
template <class Arch, class LoadCost>
void path_steps_for_count(const LoadCost& load_cost, const std::uint16_t* const* prev, const std::uint16_t* prev_min,
                          const std::uint16_t* p1, const std::uint16_t* p2, int count, int n,
                          std::uint16_t* const* out, std::uint16_t* sum, int accumulate, std::uint16_t* mins) {
  switch (count) {
    case 1: return path_steps<Arch, 1>(load_cost, prev, prev_min, p1, p2, n, out, sum, accumulate, mins);
    case 2: return path_steps<Arch, 2>(load_cost, prev, prev_min, p1, p2, n, out, sum, accumulate, mins);
    case 3: return path_steps<Arch, 3>(load_cost, prev, prev_min, p1, p2, n, out, sum, accumulate, mins);
    default: return path_steps<Arch, 4>(load_cost, prev, prev_min, p1, p2, n, out, sum, accumulate, mins);
  }
}
}  // namespace detail

template <class Arch>
void PathStepsU16<Arch>::call(const std::uint16_t* cost, const std::uint16_t* const* prev,
                              const std::uint16_t* prev_min, const std::uint16_t* p1, const std::uint16_t* p2,
                              int count, int n, std::uint16_t* const* out, std::uint16_t* sum, int accumulate,
                              std::uint16_t* mins) {
  using b16 = xsimd::batch<std::uint16_t, Arch>;
  if (n < static_cast<int>(b16::size))
    return path_steps_u16_scalar(cost, prev, prev_min, p1, p2, count, n, out, sum, accumulate, mins);
  detail::path_steps_for_count<Arch>([cost](int k) { return b16::load_unaligned(cost + k); }, prev, prev_min, p1,
                                     p2, count, n, out, sum, accumulate, mins);
}

// The byte sums' means in registers: a rounding multiply-high of 16 s (<= 4080)
// by inv_q15 (escape::mulhrs_u15).
template <class Arch>
void PathStepsU8<Arch>::call(const std::uint8_t* cost_sums, std::uint16_t inv_q15, const std::uint16_t* const* prev,
                             const std::uint16_t* prev_min, const std::uint16_t* p1, const std::uint16_t* p2,
                             int count, int n, std::uint16_t* const* out, std::uint16_t* sum, int accumulate,
                             std::uint16_t* mins) {
  using b16 = xsimd::batch<std::uint16_t, Arch>;
  if (n < static_cast<int>(b16::size))
    return path_steps_u8_scalar(cost_sums, inv_q15, prev, prev_min, p1, p2, count, n, out, sum, accumulate, mins);
  const b16 inv(inv_q15);
  detail::path_steps_for_count<Arch>(
      [cost_sums, &inv](int k) {
        return escape::mulhrs_u15(escape::load_widen_u8<Arch>(cost_sums + k) << 4, inv);
      },
      prev, prev_min, p1, p2, count, n, out, sum, accumulate, mins);
}

// ------------------------------------------------------------------ colour
// The scalar twin's loop, compiled with the arch's flags: xsimd 8 has no
// three-way deinterleave, and the compiler's grouped loads are what a hand
// version would write (pshufb on AVX2, ld3 on NEON). Plain SSE2 has no byte
// shuffle, so there the loop stays scalar (the same as the scalar twin).
// kR, kB: where red and blue sit in a triplet (RGB: 0, 2; BGR: 2, 0). A
// template of the arch too, so that each arch's file keeps its own copy.
template <class Arch, int kR, int kB>
void triplets_to_gray_row(const std::uint8_t* px, int n, std::uint8_t* gray) {
  const auto count = static_cast<std::size_t>(n > 0 ? n : 0);
  for (std::size_t x = 0; x < count; ++x) {
    const unsigned r = px[3 * x + kR], g = px[3 * x + 1], b = px[3 * x + kB];
    gray[x] = static_cast<std::uint8_t>((77u * r + 150u * g + 29u * b + 128u) >> 8);
  }
}

template <class Arch>
void RgbToGrayRowU8<Arch>::call(const std::uint8_t* rgb, int n, std::uint8_t* gray) {
  triplets_to_gray_row<Arch, 0, 2>(rgb, n, gray);
}

// The same for BGR triplets (twin: bgr_to_gray_row_scalar).
template <class Arch>
void BgrToGrayRowU8<Arch>::call(const std::uint8_t* bgr, int n, std::uint8_t* gray) {
  triplets_to_gray_row<Arch, 2, 0>(bgr, n, gray);
}

namespace detail {
// min_outside_u16 for n >= lanes: lanes j with |j - k| <= 1 ORed to 0xFFFF
// by kAround (never below any other lane); a partial last block is the full
// block ending at n.
template <class Arch>
inline std::uint16_t min_outside(const std::uint16_t* total, int n, int k) {
  using b16 = xsimd::batch<std::uint16_t, Arch>;
  constexpr int lanes = static_cast<int>(b16::size);
  const std::uint16_t* around = kAround.v + kAroundCentre - k;
  b16 r(kU16Max);
  int j = 0;
  for (; j + lanes <= n; j += lanes) r = escape::min_u16(r, b16::load_unaligned(total + j) | b16::load_unaligned(around + j));
  if (j < n) r = escape::min_u16(r, b16::load_unaligned(total + n - lanes) | b16::load_unaligned(around + n - lanes));
  return escape::hmin_u16(r);
}
}  // namespace detail

// One pass over the sums for their minimum and the right view's winners
// (total < best is min(total, best) == total and total != best: equality
// compares, which every target has for u16 lanes, SSE2 has no unsigned u16
// compare), one for the first k at the minimum, one for the rival (lanes j
// with |j - k| <= 1 ORed to 0xFFFF by kAround, which never wins). A partial
// last block is the full block ending at n; its right-view part from the
// old values read before the other blocks store theirs, so its overlapping
// lanes give the block before's results again.
template <class Arch>
int WinnerU16<Arch>::call(const std::uint16_t* total, int n, std::uint16_t* rival, std::uint16_t* best_cost,
                          std::uint16_t* best_k) {
  using b16 = xsimd::batch<std::uint16_t, Arch>;
  constexpr int lanes = static_cast<int>(b16::size);
  if (n < lanes) return winner_u16_scalar(total, n, rival, best_cost, best_k);
  const bool overlap = n % lanes != 0;
  const int tail = n - lanes;
  const b16 iota = b16::load_aligned(detail::kCount);
  b16 low(detail::kU16Max);
  if (best_cost != nullptr) {
    const auto offer = [&](int at, const b16& b, const b16& bk) {
      const b16 t = b16::load_unaligned(total + at);
      low = escape::min_u16(low, t);
      const b16 m = escape::min_u16(t, b);
      const auto take = (m == t) & (t != b);
      m.store_unaligned(best_cost + at);
      xsimd::select(take, iota + b16(static_cast<std::uint16_t>(at)), bk).store_unaligned(best_k + at);
    };
    const b16 tail_b = b16::load_unaligned(best_cost + tail), tail_k = b16::load_unaligned(best_k + tail);
    for (int j = 0; j + lanes <= n; j += lanes)
      offer(j, b16::load_unaligned(best_cost + j), b16::load_unaligned(best_k + j));
    if (overlap) offer(tail, tail_b, tail_k);
  } else {
    for (int j = 0; j + lanes <= n; j += lanes) low = escape::min_u16(low, b16::load_unaligned(total + j));
    if (overlap) low = escape::min_u16(low, b16::load_unaligned(total + tail));
  }
  // The first k at the minimum m: a min over (total == m ? k : 0xFFFF)
  // (n <= 256, so 0xFFFF is no index).
  const b16 vm(escape::hmin_u16(low)), none(detail::kU16Max);
  b16 first(detail::kU16Max);
  const auto first_in = [&](int j) {
    first = escape::min_u16(first, xsimd::select(b16::load_unaligned(total + j) == vm,
                                                 iota + b16(static_cast<std::uint16_t>(j)), none));
  };
  for (int j = 0; j + lanes <= n; j += lanes) first_in(j);
  if (overlap) first_in(tail);
  const int k = escape::hmin_u16(first);
  if (rival != nullptr) *rival = detail::min_outside<Arch>(total, n, k);
  return k;
}

template <class Arch>
std::uint16_t MinOutsideU16<Arch>::call(const std::uint16_t* total, int n, int k) {
  if (n < static_cast<int>(xsimd::batch<std::uint16_t, Arch>::size)) return min_outside_u16_scalar(total, n, k);
  return detail::min_outside<Arch>(total, n, k);
}

// A saturating add per lane; the last partial block is the full block
// ending at n (out is written, never read, so the shared lanes get the same
// value twice).
template <class Arch>
void AddSaturateU16<Arch>::call(const std::uint16_t* total, const std::uint16_t* penalty, int n,
                                std::uint16_t* out) {
  using b16 = xsimd::batch<std::uint16_t, Arch>;
  constexpr int lanes = static_cast<int>(b16::size);
  if (n < lanes) return add_saturate_u16_scalar(total, penalty, n, out);
  const auto add = [&](int j) {
    xsimd::sadd(b16::load_unaligned(total + j), b16::load_unaligned(penalty + j)).store_unaligned(out + j);
  };
  int j = 0;
  for (; j + lanes <= n; j += lanes) add(j);
  if (j < n) add(n - lanes);
}

// ---------------------------------------------------------------- tritree

namespace detail {

// x * K for a compile-time K: shifts for powers of two, nothing for 0 and 1.
template <int K, class A>
inline batch<std::int32_t, A> times(const batch<std::int32_t, A>& x) {
  if constexpr (K == 0) {
    return batch<std::int32_t, A>(0);
  } else if constexpr (K == 1) {
    return x;
  } else if constexpr (K == -1) {
    return -x;
  } else if constexpr (K > 0 && (K & (K - 1)) == 0) {
    return x << __builtin_ctz(static_cast<unsigned>(K));
  } else {
    return x * batch<std::int32_t, A>(K);
  }
}

struct LaneIndexU32 {
  static constexpr std::uint32_t get(std::size_t i, std::size_t) { return static_cast<std::uint32_t>(i); }
};
// Lane i's square: diagonal 0 ('\') or 1 ('/'), alternating from kFirstBs.
template <bool kFirstBs>
struct Side4Diagonal {
  static constexpr std::int32_t get(std::size_t i, std::size_t) { return (kFirstBs == ((i & 1) == 0)) ? 0 : 1; }
};
// Pixel kP's weight of corner kC in its half, per lane's diagonal.
template <bool kFirstBs, int kP, int kC>
struct Side4HalfWeight {
  static constexpr std::int32_t get(std::size_t i, std::size_t) {
    return side4::half_weights((kFirstBs == ((i & 1) == 0)) ? 0 : 1, kP).w[kC];
  }
};

// The pixels of side triangle k are kPixelsBySide[kSideStart[k] .. kSideStart[k + 1]).
constexpr int kPixelsBySide[16] = {0, 1, 2, 3, 5, 6, 7, 10, 11, 15, 13, 14, 4, 8, 9, 12};
constexpr int kSideStart[5] = {0, 6, 10, 12, 16};

// One side triangle's pixels: its SSE, its pixels' SSE against their half's
// plane, and their sums (I, dx I, dy I, I^2), into `group`.
template <class A, bool kFirstBs, int kSide, int... Q>
inline void side4_group(const batch<std::uint32_t, A>* row, const batch<std::int32_t, A>* corner,
                        batch<std::int32_t, A>& side_sse, batch<std::int32_t, A>* group,
                        std::integer_sequence<int, Q...>) {
  using bi = batch<std::int32_t, A>;
  using bu = batch<std::uint32_t, A>;
  const auto pixel = [&](auto q) {
    constexpr int p = kPixelsBySide[kSideStart[kSide] + decltype(q)::value];
    constexpr int dx = p & 3, dy = p >> 2;
    static_assert(side4::kSideOf[p] == kSide, "kPixelsBySide lists the side's own pixels");
    const bi v = xsimd::bitwise_cast<bi>((row[dy] >> (8 * dx)) & bu(0xFFu));
    constexpr side4::PlaneWeights ws = side4::side_weights(p);
    bi rs = times<ws.a2>(v);
    bi rh = times<side4::half_weights(0, p).a2>(v);
    static_assert(side4::half_weights(0, p).a2 == side4::half_weights(1, p).a2, "halves of one area");
    const auto corner_terms = [&](auto c) {
      constexpr int k = decltype(c)::value;
      if constexpr (ws.w[k] != 0) rs = rs - times<ws.w[k]>(corner[k]);
      constexpr int w0 = side4::half_weights(0, p).w[k], w1 = side4::half_weights(1, p).w[k];
      if constexpr (w0 == w1 && w0 != 0) {
        rh = rh - times<w0>(corner[k]);
      } else if constexpr (w0 != w1) {
        rh = rh - corner[k] * bi(xsimd::make_batch_constant<bi, Side4HalfWeight<kFirstBs, p, k>>());
      }
    };
    corner_terms(std::integral_constant<int, 0>{});
    corner_terms(std::integral_constant<int, 1>{});
    corner_terms(std::integral_constant<int, 2>{});
    corner_terms(std::integral_constant<int, 3>{});
    corner_terms(std::integral_constant<int, 4>{});
    side_sse += rs * rs;
    group[0] += rh * rh;
    group[1] += v;
    group[2] += times<dx>(v);
    group[3] += times<dy>(v);
    group[4] += v * v;
  };
  (pixel(std::integral_constant<int, Q>{}), ...);
}

// Squares m0 .. m0 + lanes - 1 of Side4TestsU8, lane i's diagonal alternating from kFirstBs.
template <class A, bool kFirstBs>
inline void side4_block(const std::uint8_t* const* rows, int m0, const std::int32_t* sse_limit,
                        std::uint32_t* wants, std::int32_t* sums, std::size_t sums_stride) {
  using bi = batch<std::int32_t, A>;
  using bu = batch<std::uint32_t, A>;
  using b8 = batch<std::uint8_t, A>;
  constexpr int lanes = static_cast<int>(bu::size);
  const int x = 4 * m0;
  // A u32 lane holds one square's 4 pixels of a row (little-endian: dx = byte).
  bu row[5];
  for (int r = 0; r < 5; ++r) row[r] = xsimd::bitwise_cast<bu>(b8::load_unaligned(rows[r] + x));
  const bu byte(0xFFu);
  // A square's right corners are its right neighbour's left ones; the last
  // lane's come from the row itself.
  const auto last_lane = bu(xsimd::make_batch_constant<bu, LaneIndexU32>()) == bu(lanes - 1);
  const auto right_corner = [&](int r) {
    const bu left = row[r] & byte;
    return xsimd::bitwise_cast<bi>(
        xsimd::select(last_lane, bu(rows[r][x + 4 * lanes]), permute<ShiftDownIdx<1>>(left)));
  };
  const bi corner[side4::kCorners] = {xsimd::bitwise_cast<bi>(row[0] & byte), right_corner(0),
                                      xsimd::bitwise_cast<bi>(row[4] & byte), right_corner(4),
                                      xsimd::bitwise_cast<bi>((row[2] >> 16) & byte)};
  const auto bs = bi(xsimd::make_batch_constant<bi, Side4Diagonal<kFirstBs>>()) == bi(0);
  const bi zero(0);
  bi bits(0), half0[5] = {zero, zero, zero, zero, zero}, half1[5] = {zero, zero, zero, zero, zero};
  const auto side = [&](auto k) {
    constexpr int kSide = decltype(k)::value;
    bi sse(0), group[5] = {zero, zero, zero, zero, zero};
    side4_group<A, kFirstBs, kSide>(row, corner, sse, group,
                                     std::make_integer_sequence<int, kSideStart[kSide + 1] - kSideStart[kSide]>{});
    bits = bits | xsimd::select(sse > bi(sse_limit[side4::kLimitSide + kSide]), bi(1 << kSide), zero);
    // The top side is in half 0, the bottom one in half 1; the right and left
    // ones in either, by the lane's diagonal (side4::half_of).
    for (int j = 0; j < 5; ++j) {
      if constexpr (kSide == 0) {
        half0[j] += group[j];
      } else if constexpr (kSide == 2) {
        half1[j] += group[j];
      } else {
        const bi in_bs = xsimd::select(bs, group[j], zero), in_slash = group[j] - in_bs;
        (kSide == 1 ? half0 : half1)[j] += in_bs;
        (kSide == 1 ? half1 : half0)[j] += in_slash;
      }
    }
  };
  side(std::integral_constant<int, 0>{});
  side(std::integral_constant<int, 1>{});
  side(std::integral_constant<int, 2>{});
  side(std::integral_constant<int, 3>{});
  const int h = side4::kLimitHalf;
  const bi limit0 = xsimd::select(bs, bi(sse_limit[h]), bi(sse_limit[h + 2]));
  const bi limit1 = xsimd::select(bs, bi(sse_limit[h + 1]), bi(sse_limit[h + 3]));
  bits = bits | xsimd::select(half0[0] > limit0, bi(1 << side4::kWantsHalfBit), zero);
  bits = bits | xsimd::select(half1[0] > limit1, bi(1 << (side4::kWantsHalfBit + 1)), zero);
  xsimd::bitwise_cast<bu>(bits).store_unaligned(wants + m0);
  for (int j = 0; j < 4; ++j) {
    half0[j + 1].store_unaligned(sums + static_cast<std::size_t>(j) * sums_stride + m0);
    half1[j + 1].store_unaligned(sums + static_cast<std::size_t>(4 + j) * sums_stride + m0);
  }
}

}  // namespace detail

// Lanes = squares. Below a register's worth of squares the narrower
// instantiation (or the scalar twin) takes them all; otherwise full blocks,
// the last one ending at n (its first lanes write the same values again).
template <class Arch>
void Side4TestsU8<Arch>::call(const std::uint8_t* const* rows, int n, int first_backslash,
                              const std::int32_t* sse_limit, std::uint32_t* wants, std::int32_t* sums,
                              std::size_t sums_stride) {
  constexpr int lanes = static_cast<int>(xsimd::batch<std::uint32_t, Arch>::size);
  if (n < lanes) {
    detail::narrower_or_scalar<Side4TestsU8, Arch>(&side4_tests_u8_scalar, rows, n, first_backslash, sse_limit,
                                                   wants, sums, sums_stride);
    return;
  }
  const auto block = [&](int m0) {
    if ((first_backslash != 0) == ((m0 & 1) == 0)) {
      detail::side4_block<Arch, true>(rows, m0, sse_limit, wants, sums, sums_stride);
    } else {
      detail::side4_block<Arch, false>(rows, m0, sse_limit, wants, sums, sums_stride);
    }
  };
  int m = 0;
  for (; m + lanes <= n; m += lanes) block(m);
  if (m < n) block(n - lanes);
}

// ---------------------------------------------------------------- side-8 tests

namespace detail {

// ARMv7 NEON has no double lanes (xsimd declares an invalid register for them).
template <class A>
struct HasDoubleLanes : std::true_type {};
template <>
struct HasDoubleLanes<xsimd::neon> : std::false_type {};

// side8::sse() on lanes of doubles: every value is an integer below 2^53, so
// each product and sum is exact (side8_shapes.hpp).
template <class A>
inline batch<double, A> side8_sse(const side8::Shape& g, const batch<double, A>* m, const batch<double, A>* corner) {
  using bd = batch<double, A>;
  const bd ia = corner[g.a], ui = corner[g.b] - ia, vi = corner[g.c] - ia;
  const bd nx = bd(g.uy) * vi - ui * bd(g.vy), ny = ui * bd(g.vx) - bd(g.ux) * vi;
  const bd sxj = m[1] - bd(g.ax) * m[0] - ia * bd(g.sx);
  const bd syj = m[2] - bd(g.ay) * m[0] - ia * bd(g.sy);
  const bd sjj = m[3] - bd(2.0) * ia * m[0] + bd(g.n) * ia * ia;
  return nx * nx * bd(g.sxx) + bd(2.0) * nx * ny * bd(g.sxy) + ny * ny * bd(g.syy) +
         bd(2.0 * g.a2) * (nx * sxj + ny * syj) + bd(double(g.a2) * g.a2) * sjj;
}

// Squares i0 .. i0 + lanes - 1 of Side8TestsS32, one per double lane.
template <class A>
inline void side8_block(const std::int32_t* const* quad_sums, std::size_t quad_stride,
                        const std::uint8_t* const* rows, int i0, int first_backslash, const std::int64_t* sse_limit,
                        std::uint32_t* wants, std::int32_t* sums, std::size_t sums_stride) {
  using bd = batch<double, A>;
  constexpr int lanes = static_cast<int>(bd::size);
  // The quadrants' halves' sums (4 x 4 squares 2 i and 2 i + 1 are the even
  // and odd lanes of the planes), moved to the square's corner.
  bd quad[2][2][2][4];  // [dy][dx][part][I, xI, yI, II]
  for (int dy = 0; dy < 2; ++dy)
    for (int part = 0; part < 2; ++part)
      for (int j = 0; j < 4; ++j)
        escape::even_odd_s32_to_f64<A>(
            quad_sums[dy] + static_cast<std::size_t>(4 * part + j) * quad_stride + static_cast<std::size_t>(2 * i0),
            quad[dy][0][part][j], quad[dy][1][part][j]);
  for (int dy = 0; dy < 2; ++dy)
    for (int dx = 0; dx < 2; ++dx)
      for (int part = 0; part < 2; ++part) {
        bd* q = quad[dy][dx][part];
        if (dx != 0) q[1] = q[1] + bd(4.0) * q[0];
        if (dy != 0) q[2] = q[2] + bd(4.0) * q[0];
      }
  // Corners: lane l's top left is row[8 l], its top right lane l + 1's top
  // left (the last lane's from the row itself), its centre row[8 l + 4].
  const int x = 8 * i0;
  bd corner[side8::kCorners];
  corner[side8::kTopLeft] = escape::bytes_every_8_to_f64<0, A>(rows[0] + x);
  corner[side8::kTopRight] = escape::shift_in_last_f64<A>(corner[side8::kTopLeft], rows[0][x + 8 * lanes]);
  corner[side8::kBottomLeft] = escape::bytes_every_8_to_f64<0, A>(rows[2] + x);
  corner[side8::kBottomRight] = escape::shift_in_last_f64<A>(corner[side8::kBottomLeft], rows[2][x + 8 * lanes]);
  corner[side8::kCentre] = escape::bytes_every_8_to_f64<4, A>(rows[1] + x);
  alignas(64) double diagonal_bs[lanes];
  for (int l = 0; l < lanes; ++l) diagonal_bs[l] = ((first_backslash != 0) == (((i0 + l) & 1) == 0)) ? 1.0 : 0.0;
  const auto bs = bd::load_aligned(diagonal_bs) != bd(0.0);
  const bd zero(0.0);
  bd side[4][4], bits(0.0);
  for (int k = 0; k < 4; ++k) {
    const int* q0 = side8::kQuad[k][0];
    const int* q1 = side8::kQuad[k][1];
    for (int j = 0; j < 4; ++j) side[k][j] = quad[q0[1]][q0[0]][q0[2]][j] + quad[q1[1]][q1[0]][q1[2]][j];
    const bd sse = side8_sse<A>(side8::kSide[k], side[k], corner);
    bits = bits + xsimd::select(sse > bd(static_cast<double>(sse_limit[side8::kLimitSide + k])), bd(double(1 << k)), zero);
  }
  // A half of each diagonal in every lane, the lane's own kept.
  for (int p = 0; p < 2; ++p) {
    bd half[2][4];
    for (int d = 0; d < 2; ++d) {
      const int* s = side8::kHalfSides[d][p];
      for (int j = 0; j < 4; ++j) half[d][j] = side[s[0]][j] + side[s[1]][j];
    }
    const bd sse = xsimd::select(bs, side8_sse<A>(side8::kHalf[0][p], half[0], corner),
                                 side8_sse<A>(side8::kHalf[1][p], half[1], corner));
    const bd limit = xsimd::select(bs, bd(static_cast<double>(sse_limit[side8::kLimitHalf + p])),
                                   bd(static_cast<double>(sse_limit[side8::kLimitHalf + 2 + p])));
    bits = bits + xsimd::select(sse > limit, bd(double(1 << (side8::kWantsHalfBit + p))), zero);
    for (int j = 0; j < 4; ++j)
      escape::store_f64_as_s32<A>(sums + static_cast<std::size_t>(4 * p + j) * sums_stride + static_cast<std::size_t>(i0),
                                  xsimd::select(bs, half[0][j], half[1][j]));
  }
  alignas(64) std::int32_t bit_words[lanes];
  escape::store_f64_as_s32<A>(bit_words, bits);
  for (int l = 0; l < lanes; ++l) wants[i0 + l] = static_cast<std::uint32_t>(bit_words[l]);
}

}  // namespace detail

// Lanes = squares, in doubles. Below a register's worth of squares (and on
// an arch without double lanes: ARMv7 NEON) the scalar twin takes them all;
// otherwise full blocks, the last one ending at n (its first lanes write the
// same values again).
template <class Arch>
void Side8TestsS32<Arch>::call(const std::int32_t* const* quad_sums, std::size_t quad_stride,
                               const std::uint8_t* const* rows, int n, int first_backslash,
                               const std::int64_t* sse_limit, std::uint32_t* wants, std::int32_t* sums,
                               std::size_t sums_stride) {
  if constexpr (!detail::HasDoubleLanes<Arch>::value) {
    side8_tests_s32_scalar(quad_sums, quad_stride, rows, n, first_backslash, sse_limit, wants, sums, sums_stride);
  } else {
    constexpr int lanes = static_cast<int>(xsimd::batch<double, Arch>::size);
    if (n < lanes) {
      side8_tests_s32_scalar(quad_sums, quad_stride, rows, n, first_backslash, sse_limit, wants, sums, sums_stride);
      return;
    }
    for (int i = 0;; i += lanes) {
      const int i0 = i + lanes <= n ? i : n - lanes;
      detail::side8_block<Arch>(quad_sums, quad_stride, rows, i0, first_backslash, sse_limit, wants, sums,
                                sums_stride);
      if (i0 + lanes >= n) break;
    }
  }
}

// Lanes = grid points, in int32 (values < 2^28, their sums wrap harmlessly
// where unused): two registers per block, narrowed to one of int16 outputs.
// Each lane computes every candidate its row kind offers and selects by its
// x's parity and quarter, from masks made for the block's start mod 4 (0 for
// every full block; the last block, ending at n, may start at 2 mod 4).
// Below a block the narrower twin or, below its block, the scalar one.
template <class Arch>
void MidpointsRowQ4<Arch>::call(const std::int32_t* above, const std::int32_t* row, const std::int32_t* below,
                                int n, int first_backslash, int frac_bits, std::int16_t* disp_q4) {
  using s32 = xsimd::batch<std::int32_t, Arch>;
  using u32 = xsimd::batch<std::uint32_t, Arch>;
  using u16 = xsimd::batch<std::uint16_t, Arch>;
  using mask = xsimd::batch_bool<std::int32_t, Arch>;
  constexpr int lanes = static_cast<int>(s32::size);
  constexpr int block = 2 * lanes;
  if (n < block) {
    detail::narrower_or_scalar<MidpointsRowQ4, Arch>(&midpoints_row_q4_scalar, above, row, below, n,
                                                     first_backslash, frac_bits, disp_q4);
    return;
  }
  alignas(64) std::int32_t x_in_block[lanes];
  for (int k = 0; k < lanes; ++k) x_in_block[k] = k;
  const s32 iota = s32::load_aligned(x_in_block);
  const s32 one(1), unknown(kMidpointUnknown), half(std::int32_t{1} << (frac_bits - 1));
  const s32 backslash_pair(first_backslash ? 0 : 1);
  struct Masks {
    mask odd, backslash;
  };
  const auto masks_at = [&](int x0) {
    const s32 x = s32(x0) + iota;
    return Masks{(x & one) == one, ((x >> 1) & one) == backslash_pair};
  };
  // One register of points from x: the known value or its average, rounded.
  const auto points = [&](int x, const Masks& m) {
    const s32 v = s32::load_unaligned(row + x);
    s32 average;
    if (above == nullptr) {
      average = (s32::load_unaligned(row + x - 1) + s32::load_unaligned(row + x + 1)) >> 1;
    } else {
      const s32 vertical = (s32::load_unaligned(above + x) + s32::load_unaligned(below + x)) >> 1;
      const s32 backslash = (s32::load_unaligned(above + x - 1) + s32::load_unaligned(below + x + 1)) >> 1;
      const s32 slash = (s32::load_unaligned(above + x + 1) + s32::load_unaligned(below + x - 1)) >> 1;
      average = xsimd::select(m.odd, xsimd::select(m.backslash, backslash, slash), vertical);
    }
    return (xsimd::select(v == unknown, average, v) + half) >> frac_bits;
  };
  const auto run = [&](int x, const Masks& m) {
    const u16 q4 = escape::narrow_u32(xsimd::bitwise_cast<u32>(points(x, m)),
                                      xsimd::bitwise_cast<u32>(points(x + lanes, m)));
    q4.store_unaligned(reinterpret_cast<std::uint16_t*>(disp_q4 + x));
  };
  const Masks from_0 = masks_at(0);
  int x = 0;
  for (; x + block <= n; x += block) run(x, from_0);
  if (x < n) run(n - block, masks_at(n - block));
}

// The rectification's remap. Each pixel's two taps of a row are one u16 load
// (p(ix, iy) | p(ix + 1, iy) << 8), gathered pixel by pixel into a stack block
// (a map points anywhere) and widened to u32 lanes holding the pair as two
// u16 halves; the weight pairs (32 - fx, fx) and (32 - fy, fy) are built the
// same way from the fractions. Two 16-bit multiply-adds per row
// (escape::madd_u16: pmaddwd on x86) give top = p00 (32 - fx) + p01 fx and
// bottom (<= 255 * 32 < 2^15), a third one top (32 - fy) + bottom fy: the
// scalar twin's integers regrouped, exact (every half < 2^15, the sum < 2^18).
// Blocks of four u32 batches of pixels; the tail goes to the scalar twin.
template <class Arch>
void RemapBilinearRowU8<Arch>::call(const std::uint8_t* src, std::size_t stride, const std::int16_t* xy,
                                    const std::uint16_t* frac, int n, std::uint8_t* out) {
  // AVX2 takes the SSE2 twin: the gather is the cost, and the wider blocks'
  // qword permutes (widen, narrow) made it slower (docs/rectification.md).
  if constexpr (!std::is_void<typename detail::Narrower<Arch>::type>::value) {
    RemapBilinearRowU8<typename detail::Narrower<Arch>::type>::call(src, stride, xy, frac, n, out);
    return;
  }
  using u8 = xsimd::batch<std::uint8_t, Arch>;
  using u16 = xsimd::batch<std::uint16_t, Arch>;
  using u32 = xsimd::batch<std::uint32_t, Arch>;
  constexpr int H = static_cast<int>(u16::size);  // pixels per half block
  constexpr int block = 2 * H;
  alignas(64) std::uint16_t top[block], bottom[block];
  const u32 k32(32), half(512);
  const u16 k31(31);
  // Results of pixels x .. x + H - 1 (their taps in top/bottom + o) as u16 lanes.
  const auto pixels = [&](int x, int o) {
    u16 t0, t1, b0, b1;
    escape::widen(u8::load_aligned(reinterpret_cast<const std::uint8_t*>(top + o)), t0, t1);
    escape::widen(u8::load_aligned(reinterpret_cast<const std::uint8_t*>(bottom + o)), b0, b1);
    const u16 f = u16::load_unaligned(frac + x);
    u32 fx0, fx1, fy0, fy1;
    escape::widen(f & k31, fx0, fx1);
    escape::widen(f >> 5, fy0, fy1);
    const auto one = [&](const u16& t, const u16& b, const u32& fx, const u32& fy) {
      const u32 wx = (k32 - fx) | (fx << 16), wy = (k32 - fy) | (fy << 16);
      const u32 rows = escape::madd_u16(xsimd::bitwise_cast<u32>(t), wx) |
                       (escape::madd_u16(xsimd::bitwise_cast<u32>(b), wx) << 16);
      return (escape::madd_u16(rows, wy) + half) >> 10;
    };
    return escape::narrow_u32(one(t0, b0, fx0, fy0), one(t1, b1, fx1, fy1));
  };
  int x = 0;
  for (; x + block <= n; x += block) {
    for (int i = 0; i < block; ++i) {
      const std::size_t j = static_cast<std::size_t>(x + i);
      const std::uint8_t* s = src + static_cast<std::size_t>(xy[2 * j + 1]) * stride + static_cast<std::size_t>(xy[2 * j]);
      std::memcpy(top + i, s, 2);
      std::memcpy(bottom + i, s + stride, 2);
    }
    escape::narrow_u16(pixels(x, 0), pixels(x + H, H)).store_unaligned(out + x);
  }
  if (x < n) remap_bilinear_row_u8_scalar(src, stride, xy + 2 * x, frac + x, n - x, out + x);
}

namespace detail {

// MidpointsRowConfQ4's blocks, of an even or an odd grid row (the row kind a
// template parameter, so that the loop carries no test of it).
template <class Arch, bool kOdd>
void midpoints_conf_blocks(const std::int32_t* above, const std::int32_t* row, const std::int32_t* below,
                           const std::uint8_t* conf_above, const std::uint8_t* conf_row,
                           const std::uint8_t* conf_below, int n, int first_backslash, int frac_bits,
                           std::int16_t* disp_q4, std::uint8_t* confidence, std::uint8_t* state) {
  using s32 = xsimd::batch<std::int32_t, Arch>;
  using u32 = xsimd::batch<std::uint32_t, Arch>;
  using u8 = xsimd::batch<std::uint8_t, Arch>;
  using s8 = xsimd::batch<std::int8_t, Arch>;
  using mask = xsimd::batch_bool<std::int32_t, Arch>;
  using mask8 = xsimd::batch_bool<std::uint8_t, Arch>;
  constexpr int lanes = static_cast<int>(s32::size);
  constexpr int block = 4 * lanes;  // = u8::size
  static_assert(block == static_cast<int>(u8::size), "four int32 registers narrow to one of bytes");
  alignas(64) std::int32_t x_in_block[lanes];
  for (int j = 0; j < lanes; ++j) x_in_block[j] = j;
  const s32 iota = s32::load_aligned(x_in_block);
  const s32 one(1), unknown(kMidpointUnknown), half(std::int32_t{1} << (frac_bits - 1));
  const s32 backslash_pair(first_backslash ? 0 : 1), all_ones(-1), zero(0);
  // The parity and quarter masks for a block from x0, in int32 lanes (for
  // the values) and in bytes (for the confidences).
  struct Masks {
    mask odd, backslash;
    mask8 odd8, backslash8;
  };
  const auto masks_at = [&](int x0) {
    const s32 x = s32(x0) + iota;
    alignas(64) std::uint8_t odd_bytes[block], backslash_bytes[block];
    for (int j = 0; j < block; ++j) {
      odd_bytes[j] = ((x0 + j) & 1) != 0 ? 0xFF : 0;
      backslash_bytes[j] = (((x0 + j) >> 1) & 1) == (first_backslash ? 0 : 1) ? 0xFF : 0;
    }
    return Masks{(x & one) == one, ((x >> 1) & one) == backslash_pair,
                 u8::load_aligned(odd_bytes) != u8(0), u8::load_aligned(backslash_bytes) != u8(0)};
  };
  const auto load = [](const std::int32_t* p) { return s32::load_unaligned(p); };
  const auto load8 = [](const std::uint8_t* p) { return u8::load_unaligned(p); };
  const auto narrow = [](const s32& a, const s32& b) {
    return escape::narrow_u32(xsimd::bitwise_cast<u32>(a), xsimd::bitwise_cast<u32>(b));
  };
  const auto run = [&](int x0, const Masks& m) {
    s32 q4[4], unknown_lanes[4];
    for (int r = 0; r < 4; ++r) {
      const int x = x0 + r * lanes;
      const s32 v = load(row + x);
      s32 average;
      if constexpr (!kOdd) {
        average = (load(row + x - 1) + load(row + x + 1)) >> 1;
      } else {
        const s32 vertical = (load(above + x) + load(below + x)) >> 1;
        const s32 backslash = (load(above + x - 1) + load(below + x + 1)) >> 1;
        const s32 slash = (load(above + x + 1) + load(below + x - 1)) >> 1;
        average = xsimd::select(m.odd, xsimd::select(m.backslash, backslash, slash), vertical);
      }
      const auto is_unknown = v == unknown;
      q4[r] = (xsimd::select(is_unknown, average, v) + half) >> frac_bits;
      unknown_lanes[r] = xsimd::select(is_unknown, all_ones, zero);
    }
    narrow(q4[0], q4[1]).store_unaligned(reinterpret_cast<std::uint16_t*>(disp_q4 + x0));
    narrow(q4[2], q4[3]).store_unaligned(reinterpret_cast<std::uint16_t*>(disp_q4 + x0 + 2 * lanes));
    // The confidences, a register of bytes for the whole block.
    const mask8 unknown8 = escape::narrow_u16(narrow(unknown_lanes[0], unknown_lanes[1]),
                                              narrow(unknown_lanes[2], unknown_lanes[3])) != u8(0);
    u8 least;
    if constexpr (!kOdd) {
      least = escape::min_u8(load8(conf_row + x0 - 1), load8(conf_row + x0 + 1));
    } else {
      const u8 vertical = escape::min_u8(load8(conf_above + x0), load8(conf_below + x0));
      const u8 backslash = escape::min_u8(load8(conf_above + x0 - 1), load8(conf_below + x0 + 1));
      const u8 slash = escape::min_u8(load8(conf_above + x0 + 1), load8(conf_below + x0 - 1));
      least = xsimd::select(m.odd8, xsimd::select(m.backslash8, backslash, slash), vertical);
    }
    const u8 c = xsimd::select(unknown8, least, load8(conf_row + x0));
    c.store_unaligned(confidence + x0);
    // State 0, 1 or 2: 2 from 128 (negative as int8), else 1 unless 0.
    const s8 c8 = xsimd::bitwise_cast<s8>(c);
    const s8 st = xsimd::select(c8 < s8(0), s8(2), xsimd::select(c8 == s8(0), s8(0), s8(1)));
    st.store_unaligned(reinterpret_cast<std::int8_t*>(state + x0));
  };
  const Masks from_0 = masks_at(0);
  int x = 0;
  for (; x + block <= n; x += block) run(x, from_0);
  if (x < n) run(n - block, masks_at(n - block));
}

}  // namespace detail

// The same lanes and masks as MidpointsRowQ4 for the values; the
// confidences in bytes beside them, each unknown point's the minimum of its
// pair's, selected like the average (by the values' unknown lanes, narrowed
// to bytes). Blocks of four int32 registers, one register of bytes; the last
// block ends at n, as there.
template <class Arch>
void MidpointsRowConfQ4<Arch>::call(const std::int32_t* above, const std::int32_t* row, const std::int32_t* below,
                                    const std::uint8_t* conf_above, const std::uint8_t* conf_row,
                                    const std::uint8_t* conf_below, int n, int first_backslash, int frac_bits,
                                    std::int16_t* disp_q4, std::uint8_t* confidence, std::uint8_t* state) {
  constexpr int block = 4 * static_cast<int>(xsimd::batch<std::int32_t, Arch>::size);
  if (n < block) {
    detail::narrower_or_scalar<MidpointsRowConfQ4, Arch>(&midpoints_row_conf_q4_scalar, above, row, below,
                                                         conf_above, conf_row, conf_below, n, first_backslash,
                                                         frac_bits, disp_q4, confidence, state);
  } else if (above == nullptr) {
    detail::midpoints_conf_blocks<Arch, false>(above, row, below, conf_above, conf_row, conf_below, n,
                                               first_backslash, frac_bits, disp_q4, confidence, state);
  } else {
    detail::midpoints_conf_blocks<Arch, true>(above, row, below, conf_above, conf_row, conf_below, n,
                                              first_backslash, frac_bits, disp_q4, confidence, state);
  }
}

}  // namespace simd
}  // namespace tristereo
