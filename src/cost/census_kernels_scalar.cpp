// Scalar census kernels: the readable definition of the census transform and
// of the Hamming cost over a support window (docs/model.md section 2).
#include <cstdint>

#include "src/kernels/kernels_scalar.hpp"

namespace tristereo {

// Bits set in v, counted in pairs, nibbles, then the byte (the SIMD twins
// count each byte lane the same way or with a nibble table).
int census_popcount_u8(std::uint8_t v) {
  unsigned x = v;
  x = x - ((x >> 1) & 0x55u);
  x = (x & 0x33u) + ((x >> 2) & 0x33u);
  return static_cast<int>((x + (x >> 4)) & 0x0Fu);
}

// The descriptor in byte planes: eight bits per plane, so that the costs
// count one byte lane per disparity (twice the disparities per register of
// 16-bit planes; three planes for the default 5x5 window instead of two
// 16-bit ones, a quarter of whose bits would be empty).
void census_row_u8_scalar(const std::uint8_t* const* rows, int win_w, int win_h, int width,
                           std::uint8_t* const* planes) {
  const int rx = win_w / 2, ry = win_h / 2;
  const int n_planes = (win_w * win_h - 1 + 7) / 8;
  for (int x = 0; x < width; ++x) {
    const std::uint8_t centre = rows[ry][x];
    std::uint8_t bits[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    int b = 0;
    for (int dy = 0; dy < win_h; ++dy)
      for (int dx = -rx; dx <= rx; ++dx) {
        if (dy == ry && dx == 0) continue;  // the centre has no bit
        if (rows[dy][x + dx] < centre) bits[b >> 3] = static_cast<std::uint8_t>(bits[b >> 3] | (1u << (b & 7)));
        ++b;
      }
    for (int p = 0; p < n_planes; ++p) planes[p][x] = bits[p];
  }
}

void census_window_u16_scalar(const std::uint8_t* const* right_rev, const std::uint8_t* left,
                              int count, int n, std::uint16_t* sum) {
  for (int k = 0; k < n; ++k) {
    int s = 0;
    for (int i = 0; i < count; ++i) s += census_popcount_u8(static_cast<std::uint8_t>(left[i] ^ right_rev[i][k]));
    sum[k] = static_cast<std::uint16_t>(s);
  }
}

namespace {
template <class T>
void census_costs_row(const std::uint8_t* const* right_rev, const std::uint8_t* const* left, int planes,
                      int width, int n, std::size_t stride, T* out) {
  for (int x = 0; x < width; ++x)
    for (int k = 0; k < n; ++k) {
      int s = 0;
      for (int p = 0; p < planes; ++p)
        s += census_popcount_u8(static_cast<std::uint8_t>(left[p][x] ^ right_rev[p][k - x]));
      out[static_cast<std::size_t>(x) * stride + static_cast<std::size_t>(k)] = static_cast<T>(s);
    }
}
}  // namespace

void census_costs_row_u16_scalar(const std::uint8_t* const* right_rev, const std::uint8_t* const* left,
                                 int planes, int width, int n, std::size_t stride, std::uint16_t* out) {
  census_costs_row(right_rev, left, planes, width, n, stride, out);
}

void census_costs_row_u8_scalar(const std::uint8_t* const* right_rev, const std::uint8_t* const* left,
                                int planes, int width, int n, std::size_t stride, std::uint8_t* out) {
  census_costs_row(right_rev, left, planes, width, n, stride, out);
}

namespace {
template <class T>
void sum_rows(const T* const* rows, int count, std::size_t n, T* sum) {
  for (std::size_t j = 0; j < n; ++j) {
    std::uint32_t s = 0;
    for (int i = 0; i < count; ++i) s += rows[i][j];
    sum[j] = static_cast<T>(s);
  }
}
}  // namespace

void sum_rows_u8_scalar(const std::uint8_t* const* rows, int count, std::size_t n, std::uint8_t* sum) {
  sum_rows(rows, count, n, sum);
}

void sum_rows_u16_scalar(const std::uint16_t* const* rows, int count, std::size_t n, std::uint16_t* sum) {
  sum_rows(rows, count, n, sum);
}

}  // namespace tristereo
