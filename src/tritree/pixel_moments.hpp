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

}  // namespace tristereo
