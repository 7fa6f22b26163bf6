// The support prior's plane of a segment (docs/model.md section 6b): an
// integer least-squares fit with a documented rounding, shared by nothing
// else. All arithmetic is int64 and exact (no __int128: armhf has none).
#pragma once

#include <cstdint>

#include "tristereo/fixed_point.hpp"

namespace tristereo {

// Second moments about a centroid.
struct PlaneMoments {
  std::int64_t uu = 0, uv = 0, vv = 0, uw = 0, vw = 0, su = 0, sv = 0, sw = 0;
};

// Raw sums over a fit set of n >= 1 points (x, y, d), d in Q4: one pass
// gives the centroid and, exactly, the moments about it. With x, y < 2^12,
// |d| < 2^15 and n <= 2^24 every sum and every term of moments() is below
// 2^52, so int64 holds them with room to spare.
struct PlaneSums {
  std::int64_t n = 0, sx = 0, sy = 0, sd = 0, sxx = 0, sxy = 0, syy = 0, sxd = 0, syd = 0;
  void add(std::int64_t x, std::int64_t y, std::int64_t d) {
    ++n;
    sx += x;
    sy += y;
    sd += d;
    sxx += x * x;
    sxy += x * y;
    syy += y * y;
    sxd += x * d;
    syd += y * d;
  }
  bool operator==(const PlaneSums& o) const {
    return n == o.n && sx == o.sx && sy == o.sy && sd == o.sd && sxx == o.sxx && sxy == o.sxy && syy == o.syy &&
           sxd == o.sxd && syd == o.syd;
  }
  void merge(const PlaneSums& o) {
    n += o.n;
    sx += o.sx;
    sy += o.sy;
    sd += o.sd;
    sxx += o.sxx;
    sxy += o.sxy;
    syy += o.syy;
    sxd += o.sxd;
    syd += o.syd;
  }
  // The moments of u = x - xb, v = y - yb, w = d - db (the sums expanded).
  PlaneMoments moments(std::int64_t xb, std::int64_t yb, std::int64_t db) const {
    PlaneMoments m;
    m.uu = sxx - 2 * xb * sx + n * xb * xb;
    m.uv = sxy - xb * sy - yb * sx + n * xb * yb;
    m.vv = syy - 2 * yb * sy + n * yb * yb;
    m.uw = sxd - xb * sd - db * sx + n * xb * db;
    m.vw = syd - yb * sd - db * sy + n * yb * db;
    m.su = sx - n * xb;
    m.sv = sy - n * yb;
    m.sw = sd - n * db;
    return m;
  }
};

// d(x, y) = dbar + floor((c + a (x - xbar) + b (y - ybar) + 128) / 256), a, b, c in Q8.
struct IntPlane {
  int xbar = 0, ybar = 0, dbar = 0;
  std::int64_t a = 0, b = 0, c = 0;
  int at(int x, int y) const {
    return dbar + static_cast<int>(floor_div(c + a * (x - xbar) + b * (y - ybar) + 128, 256));
  }
  // t with floor(t / 256) = at(x, y) - d: |at - d| <= m exactly when
  // -256 m <= t < 256 (m + 1), two compares instead of a division.
  std::int64_t residual_q8(int x, int y, int d) const {
    return c + a * (x - xbar) + b * (y - ybar) + 128 - 256 * std::int64_t{d - dbar};
  }
};

inline std::int64_t abs64(std::int64_t v) { return v < 0 ? -v : v; }

// The plane from the moments (n points about the centroid of `p`); false when
// degenerate (det <= 0) or steeper than 2^20 / 256 Q4 per pixel.
inline bool solve_plane(const PlaneMoments& m, std::int64_t n, IntPlane* p) {
  std::int64_t big = abs64(m.uu);
  for (std::int64_t v : {m.uv, m.vv, m.uw, m.vw}) big = abs64(v) > big ? abs64(v) : big;
  int s = 0;
  while ((big >> s) >= (std::int64_t{1} << 26)) ++s;
  const std::int64_t uu = m.uu >> s, uv = m.uv >> s, vv = m.vv >> s, uw = m.uw >> s, vw = m.vw >> s;
  const std::int64_t det = uu * vv - uv * uv;
  if (det <= 0) return false;
  const std::int64_t an = uw * vv - vw * uv, bn = vw * uu - uw * uv;
  const std::int64_t a = floor_div(512 * an + det, 2 * det), b = floor_div(512 * bn + det, 2 * det);
  if (abs64(a) > (std::int64_t{1} << 20) || abs64(b) > (std::int64_t{1} << 20)) return false;
  p->a = a;
  p->b = b;
  p->c = floor_div(2 * (256 * m.sw - a * m.su - b * m.sv) + n, 2 * n);
  return true;
}

}  // namespace tristereo
