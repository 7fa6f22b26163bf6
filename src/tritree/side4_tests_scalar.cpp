// The side-4 level's plane tests, scalar: the readable reference of
// KernelSet::side4_tests_u8 (src/kernels/kernel_set.hpp), pixel by pixel as
// side4_shapes.hpp defines them.
#include "src/kernels/kernels_scalar.hpp"
#include "src/tritree/side4_shapes.hpp"

namespace tristereo {

namespace {

// Every pixel's weights, once, at compile time (called at run time, the
// constexpr functions cost more than the tests).
struct Side4Tables {
  side4::PlaneWeights side[16];
  side4::PlaneWeights half[2][16];
};
constexpr Side4Tables make_side4_tables() {
  Side4Tables t{};
  for (int p = 0; p < 16; ++p) {
    t.side[p] = side4::side_weights(p);
    t.half[0][p] = side4::half_weights(0, p);
    t.half[1][p] = side4::half_weights(1, p);
  }
  return t;
}
constexpr Side4Tables kSide4Tables = make_side4_tables();

// a2 I - sum of w_c I_c over the five corners (unused ones weigh 0).
inline std::int32_t plane_residual(const side4::PlaneWeights& pw, std::int32_t v, const std::int32_t* corner) {
  return pw.a2 * v - (pw.w[0] * corner[0] + pw.w[1] * corner[1] + pw.w[2] * corner[2] + pw.w[3] * corner[3] +
                      pw.w[4] * corner[4]);
}

}  // namespace

void side4_tests_u8_scalar(const std::uint8_t* const* rows, int n, int first_backslash,
                           const std::int32_t* sse_limit, std::uint32_t* wants, std::int32_t* sums,
                           std::size_t sums_stride) {
  using namespace side4;
  for (int m = 0; m < n; ++m) {
    const int x = 4 * m;
    const int diagonal = ((first_backslash != 0) == ((m & 1) == 0)) ? 0 : 1;  // alternate along the row
    const std::int32_t corner[kCorners] = {rows[0][x], rows[0][x + 4], rows[4][x], rows[4][x + 4],
                                           rows[2][x + 2]};
    std::int32_t side_sse[4] = {0, 0, 0, 0}, half_sse[2] = {0, 0};
    std::int32_t half_sum[2][4] = {{0, 0, 0, 0}, {0, 0, 0, 0}};  // I, dx I, dy I, I^2
    // Unrolled, every weight is a constant: zeros vanish, powers of two shift.
#if defined(__clang__)
#pragma unroll
#elif defined(__GNUC__)
#pragma GCC unroll 16
#endif
    for (int p = 0; p < 16; ++p) {
      const int dx = p & 3, dy = p >> 2;
      const std::int32_t v = rows[dy][x + dx];
      const int h = half_of(diagonal, kSideOf[p]);
      const std::int32_t rs = plane_residual(kSide4Tables.side[p], v, corner);
      const std::int32_t rh = plane_residual(kSide4Tables.half[diagonal][p], v, corner);
      side_sse[kSideOf[p]] += rs * rs;
      half_sse[h] += rh * rh;
      half_sum[h][0] += v;
      half_sum[h][1] += dx * v;
      half_sum[h][2] += dy * v;
      half_sum[h][3] += v * v;
    }
    std::uint32_t bits = 0;
    for (int k = 0; k < 4; ++k) bits |= static_cast<std::uint32_t>(side_sse[k] > sse_limit[kLimitSide + k]) << k;
    for (int h = 0; h < 2; ++h)
      bits |= static_cast<std::uint32_t>(half_sse[h] > sse_limit[kLimitHalf + 2 * diagonal + h])
              << (kWantsHalfBit + h);
    wants[m] = bits;
    for (int c = 0; c < 8; ++c) sums[static_cast<std::size_t>(c) * sums_stride + m] = half_sum[c / 4][c % 4];
  }
}

}  // namespace tristereo
