// Scalar census kernels: the readable definition of the census transform and
// of the Hamming cost over a support window (docs/model.md section 2).
#include <cstdint>

#include "src/kernels/kernels_scalar.hpp"

namespace tristereo {

// Bits set in v, counted in pairs, nibbles, then bytes (the SIMD twins count
// each lane the same way).
int census_popcount_u16(std::uint16_t v) {
  unsigned x = v;
  x = x - ((x >> 1) & 0x5555u);
  x = (x & 0x3333u) + ((x >> 2) & 0x3333u);
  x = (x + (x >> 4)) & 0x0F0Fu;
  return static_cast<int>((x + (x >> 8)) & 0x1Fu);
}

void census_row_u8_scalar(const std::uint8_t* const* rows, int win_w, int win_h, int width,
                           std::uint16_t* const* planes) {
  const int rx = win_w / 2, ry = win_h / 2;
  const int n_planes = (win_w * win_h - 1 + 15) / 16;
  for (int x = 0; x < width; ++x) {
    const std::uint16_t centre = rows[ry][x];
    std::uint16_t bits[4] = {0, 0, 0, 0};
    int b = 0;
    for (int dy = 0; dy < win_h; ++dy)
      for (int dx = -rx; dx <= rx; ++dx) {
        if (dy == ry && dx == 0) continue;  // the centre has no bit
        if (rows[dy][x + dx] < centre) bits[b >> 4] = static_cast<std::uint16_t>(bits[b >> 4] | (1u << (b & 15)));
        ++b;
      }
    for (int p = 0; p < n_planes; ++p) planes[p][x] = bits[p];
  }
}

void census_window_u16_scalar(const std::uint16_t* const* right_rev, const std::uint16_t* left,
                              int count, int n, std::uint16_t* sum) {
  for (int k = 0; k < n; ++k) {
    int s = 0;
    for (int i = 0; i < count; ++i)
      s += census_popcount_u16(static_cast<std::uint16_t>(left[i] ^ right_rev[i][k]));
    sum[k] = static_cast<std::uint16_t>(s);
  }
}

namespace {
template <class T>
void census_costs_row(const std::uint16_t* const* right_rev, const std::uint16_t* const* left, int planes,
                      int width, int n, std::size_t stride, T* out) {
  for (int x = 0; x < width; ++x)
    for (int k = 0; k < n; ++k) {
      int s = 0;
      for (int p = 0; p < planes; ++p)
        s += census_popcount_u16(static_cast<std::uint16_t>(left[p][x] ^ right_rev[p][k - x]));
      out[static_cast<std::size_t>(x) * stride + static_cast<std::size_t>(k)] = static_cast<T>(s);
    }
}
}  // namespace

void census_costs_row_u16_scalar(const std::uint16_t* const* right_rev, const std::uint16_t* const* left,
                                 int planes, int width, int n, std::size_t stride, std::uint16_t* out) {
  census_costs_row(right_rev, left, planes, width, n, stride, out);
}

void census_costs_row_u8_scalar(const std::uint16_t* const* right_rev, const std::uint16_t* const* left,
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
