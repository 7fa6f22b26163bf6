// The support prior's plane of a segment (docs/model.md section 6b): an
// integer least-squares fit with a documented rounding, shared by nothing
// else. All arithmetic is int64 and exact (no __int128: armhf has none).
#pragma once

#include <cstdint>

#include "tristereo/fixed_point.hpp"

namespace tristereo {

// Sums over a fit set of n >= 1 points (x, y, d), d in Q4.
struct PlaneSums {
  std::int64_t n = 0, sx = 0, sy = 0, sd = 0;
  void add(int x, int y, int d) {
    ++n;
    sx += x;
    sy += y;
    sd += d;
  }
};

// d(x, y) = dbar + floor((c + a (x - xbar) + b (y - ybar) + 128) / 256), a, b, c in Q8.
struct IntPlane {
  int xbar = 0, ybar = 0, dbar = 0;
  std::int64_t a = 0, b = 0, c = 0;
  int at(int x, int y) const {
    return dbar + static_cast<int>(floor_div(c + a * (x - xbar) + b * (y - ybar) + 128, 256));
  }
};

// Second moments about the floored centroid.
struct PlaneMoments {
  std::int64_t uu = 0, uv = 0, vv = 0, uw = 0, vw = 0, su = 0, sv = 0, sw = 0;
  void add(int u, int v, int w) {
    uu += std::int64_t{u} * u;
    uv += std::int64_t{u} * v;
    vv += std::int64_t{v} * v;
    uw += std::int64_t{u} * w;
    vw += std::int64_t{v} * w;
    su += u;
    sv += v;
    sw += w;
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
