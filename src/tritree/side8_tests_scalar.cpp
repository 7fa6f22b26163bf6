// The side-8 level's plane tests, scalar: the readable reference of
// KernelSet::side8_tests_s32 (src/kernels/kernel_set.hpp), square by square
// as side8_shapes.hpp defines them.
#include "src/kernels/kernels_scalar.hpp"
#include "src/tritree/side8_shapes.hpp"

namespace tristereo {

void side8_tests_s32_scalar(const std::int32_t* const* quad_sums, std::size_t quad_stride,
                            const std::uint8_t* const* rows, int n, int first_backslash,
                            const std::int64_t* sse_limit, std::uint32_t* wants, std::int32_t* sums,
                            std::size_t sums_stride) {
  using namespace side8;
  for (int i = 0; i < n; ++i) {
    const int x = 8 * i;
    const int diagonal = ((first_backslash != 0) == ((i & 1) == 0)) ? 0 : 1;  // alternate along the row
    const std::int32_t corner[kCorners] = {rows[0][x], rows[0][x + 8], rows[2][x], rows[2][x + 8], rows[1][x + 4]};
    // The quadrants' halves' sums, moved to the square's corner.
    std::int64_t quad[2][2][2][4];  // [dy][dx][part][I, xI, yI, II]
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx)
        for (int part = 0; part < 2; ++part) {
          std::int64_t* q = quad[dy][dx][part];
          for (int j = 0; j < 4; ++j)
            q[j] = quad_sums[dy][static_cast<std::size_t>(4 * part + j) * quad_stride + static_cast<std::size_t>(2 * i + dx)];
          q[1] += 4 * dx * q[0];
          q[2] += 4 * dy * q[0];
        }
    std::int64_t side[4][4];
    std::uint32_t bits = 0;
    for (int k = 0; k < 4; ++k) {
      const int* q0 = kQuad[k][0];
      const int* q1 = kQuad[k][1];
      for (int j = 0; j < 4; ++j) side[k][j] = quad[q0[1]][q0[0]][q0[2]][j] + quad[q1[1]][q1[0]][q1[2]][j];
      bits |= static_cast<std::uint32_t>(side8::sse(kSide[k], side[k], corner) > sse_limit[kLimitSide + k]) << k;
    }
    for (int p = 0; p < 2; ++p) {
      std::int64_t half[4];
      const int* s = kHalfSides[diagonal][p];
      for (int j = 0; j < 4; ++j) half[j] = side[s[0]][j] + side[s[1]][j];
      bits |= static_cast<std::uint32_t>(side8::sse(kHalf[diagonal][p], half, corner) >
                                         sse_limit[kLimitHalf + 2 * diagonal + p])
              << (kWantsHalfBit + p);
      for (int j = 0; j < 4; ++j)
        sums[static_cast<std::size_t>(4 * p + j) * sums_stride + static_cast<std::size_t>(i)] =
            static_cast<std::int32_t>(half[j]);
    }
    wants[i] = bits;
  }
}

}  // namespace tristereo
