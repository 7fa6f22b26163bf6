// The tritree's split test from pixel moments (docs/model.md section 1).
//
// The squared residual of the plane through a triangle's three corners,
//   SSE = sum over owned pixels of (n_x x + n_y y + area2 I + k)^2,
// expands into ten sums over the owned pixels (n, x, y, xx, xy, yy, I, xI,
// yI, II). Ownership is a partition (each pixel goes to the triangle that
// contains the pixel nudged by the fill rule), so a triangle's sums are its
// two children's sums added: built bottom-up once per frame, every test is
// O(1). Coordinates are relative to a tile origin (< 2^7), so every sum of a
// triangle with area <= kMaxAreaLimitPx2 fits int32.
#pragma once

#include <cstdint>
#include <type_traits>

namespace tristereo {

struct PixelMoments {
  std::int32_t n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0, si = 0, sxi = 0, syi = 0, sii = 0;

  void add_pixel(std::int32_t x, std::int32_t y, std::int32_t i) {
    n += 1;
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    syy += y * y;
    si += i;
    sxi += x * i;
    syi += y * i;
    sii += i * i;
  }
  PixelMoments& operator+=(const PixelMoments& o) {
    n += o.n;
    sx += o.sx;
    sy += o.sy;
    sxx += o.sxx;
    sxy += o.sxy;
    syy += o.syy;
    si += o.si;
    sxi += o.sxi;
    syi += o.syi;
    sii += o.sii;
    return *this;
  }
  friend PixelMoments operator+(PixelMoments a, const PixelMoments& b) { return a += b; }
  bool operator==(const PixelMoments& o) const {
    return n == o.n && sx == o.sx && sy == o.sy && sxx == o.sxx && sxy == o.sxy && syy == o.syy &&
           si == o.si && sxi == o.sxi && syi == o.syi && sii == o.sii;
  }
};

// A triangle corner for the test: position (relative to the moments' origin)
// and intensity.
struct PlaneCorner {
  std::int32_t x, y, i;
};

// Sum of squared residuals r = n_x x + n_y y + area2 I + k over the pixels of
// `m`, with n = (b - a) x (c - a) in (x, y, I) and k such that r(a) = 0.
// Computed in uint64 arithmetic, which wraps modulo 2^64: intermediate terms
// may exceed 2^63, but the true SSE is below 2^52 for every triangle the model
// tests (docs/model.md section 5), so the wrapped result is the exact value.
inline std::uint64_t plane_sse(const PixelMoments& m, const PlaneCorner& a, const PlaneCorner& b,
                               const PlaneCorner& c) {
  const std::int64_t ux = b.x - a.x, uy = b.y - a.y, ui = b.i - a.i;
  const std::int64_t vx = c.x - a.x, vy = c.y - a.y, vi = c.i - a.i;
  const std::uint64_t nx = static_cast<std::uint64_t>(uy * vi - ui * vy);
  const std::uint64_t ny = static_cast<std::uint64_t>(ui * vx - ux * vi);
  const std::uint64_t nz = static_cast<std::uint64_t>(ux * vy - uy * vx);  // area2
  const std::uint64_t k =
      0 - (nx * static_cast<std::uint64_t>(a.x) + ny * static_cast<std::uint64_t>(a.y) +
           nz * static_cast<std::uint64_t>(a.i));
  const auto u = [](std::int32_t v) { return static_cast<std::uint64_t>(static_cast<std::int64_t>(v)); };
  const std::uint64_t square_terms =
      nx * nx * u(m.sxx) + ny * ny * u(m.syy) + nz * nz * u(m.sii) + k * k * u(m.n);
  const std::uint64_t cross_terms = nx * ny * u(m.sxy) + nx * nz * u(m.sxi) + ny * nz * u(m.syi) +
                                    k * (nx * u(m.sx) + ny * u(m.sy) + nz * u(m.si));
  return square_terms + 2 * cross_terms;
}

// The model's PSNR test on exact integers: SSE * 256 > mse_q8 * n_px * area2^2.
inline bool plane_fit_fails(std::uint64_t sse, std::int64_t n_px, std::int64_t area2,
                            std::uint64_t mse_q8) {
  const std::uint64_t a2 = static_cast<std::uint64_t>(area2);
  return sse * 256 > mse_q8 * static_cast<std::uint64_t>(n_px) * a2 * a2;
}

// Inside a plain tile (away from the image's last row and column) a
// triangle's pixels, relative to its first corner A, depend only on its shape
// (size and orientation): the geometric sums are constants of the shape, and
// only four sums of the image remain per triangle.
struct IntensityMoments {
  std::int32_t si = 0, sxi = 0, syi = 0, sii = 0;  // x, y relative to the tile origin

  void add_pixel(std::int32_t x, std::int32_t y, std::int32_t i) {
    si += i;
    sxi += x * i;
    syi += y * i;
    sii += i * i;
  }
  friend IntensityMoments operator+(const IntensityMoments& a, const IntensityMoments& b) {
    return IntensityMoments{a.si + b.si, a.sxi + b.sxi, a.syi + b.syi, a.sii + b.sii};
  }
};

// A triangle shape (A, B = A + u, C = A + v, area2 = u x v > 0) and the sums
// over its owned pixels P of 1, x', y', x'^2, x'y', y'^2 with (x', y') = P - A.
struct ShapeMoments {
  std::int32_t ux = 0, uy = 0, vx = 0, vy = 0, area2 = 0;
  std::int32_t n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
  // plane_fit_fails' right-hand side for this shape, mse_q8 * n * area2^2,
  // once the threshold is known (Tritree::configure): the test is then
  // SSE * 256 > fail_above_q8.
  std::uint64_t fail_above_q8 = 0;
};

// plane_sse() for a triangle of shape g with first corner (ax, ay) (relative
// to the tile origin of m) and corner intensities ia, ib, ic, the shape's edge
// vectors u = B - A and v = C - A given as (ux, uy, vx, vy): ints, or
// std::integral_constant when they are known at compile time (the products
// by 0, +-1 and powers of two then fold away). With J = I - ia and
// (x', y') = P - A, r = n_x x' + n_y y' + area2 J, so
//   SSE = n_x^2 Sx'x' + 2 n_x n_y Sx'y' + n_y^2 Sy'y'
//       + 2 area2 (n_x Sx'J + n_y Sy'J) + area2^2 SJJ.
// The same uint64 wrap-around argument as plane_sse(): exact below 2^64.
template <class Ux, class Uy, class Vx, class Vy>
inline std::uint64_t plane_sse_with_edges(const IntensityMoments& m, const ShapeMoments& g, std::int32_t ax,
                                          std::int32_t ay, std::int32_t ia, std::int32_t ib, std::int32_t ic,
                                          Ux ux, Uy uy, Vx vx, Vy vy) {
  const std::int64_t a2 = std::int64_t{ux} * vy - std::int64_t{uy} * vx;
  const std::int64_t ui = ib - ia, vi = ic - ia;
  const std::int64_t nx = uy * vi - ui * vy;
  const std::int64_t ny = ui * vx - ux * vi;
  const std::int64_t sxj = (std::int64_t{m.sxi} - std::int64_t{ax} * m.si) - std::int64_t{ia} * g.sx;
  const std::int64_t syj = (std::int64_t{m.syi} - std::int64_t{ay} * m.si) - std::int64_t{ia} * g.sy;
  const std::int64_t sjj = std::int64_t{m.sii} - 2 * std::int64_t{ia} * m.si + std::int64_t{g.n} * ia * ia;
  const auto u = [](std::int64_t v) { return static_cast<std::uint64_t>(v); };
  return u(nx * nx) * u(g.sxx) + 2 * u(nx * ny) * u(g.sxy) + u(ny * ny) * u(g.syy) +
         2 * u(a2) * (u(nx) * u(sxj) + u(ny) * u(syj)) + u(a2 * a2) * u(sjj);
}

// The shape's edges from g itself.
inline std::uint64_t plane_sse_of_shape(const IntensityMoments& m, const ShapeMoments& g, std::int32_t ax,
                                        std::int32_t ay, std::int32_t ia, std::int32_t ib, std::int32_t ic) {
  return plane_sse_with_edges(m, g, ax, ay, ia, ib, ic, g.ux, g.uy, g.vx, g.vy);
}

// The edges known at compile time (the RTIN shapes of a plain tile of known
// side): g supplies the geometric sums only (its u and v must be these).
template <int kUx, int kUy, int kVx, int kVy>
inline std::uint64_t plane_sse_of_fixed_shape(const IntensityMoments& m, const ShapeMoments& g, std::int32_t ax,
                                              std::int32_t ay, std::int32_t ia, std::int32_t ib, std::int32_t ic) {
  static_assert(std::int64_t{kUx} * kVy - std::int64_t{kUy} * kVx > 0, "positive orientation");
  return plane_sse_with_edges(m, g, ax, ay, ia, ib, ic, std::integral_constant<int, kUx>{},
                              std::integral_constant<int, kUy>{}, std::integral_constant<int, kVx>{},
                              std::integral_constant<int, kVy>{});
}

}  // namespace tristereo
