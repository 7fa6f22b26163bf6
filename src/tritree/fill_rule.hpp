// Pixel ownership of a tritree triangle (docs/model.md section 1, "Pixel
// ownership"): which pixel centres a triangle (a, b, c) with area2 > 0 owns.
//
// Pixel P belongs to T when, for each directed edge U -> V of (a->b, b->c,
// c->a), E = (Vx-Ux)(Py-Uy) - (Vy-Uy)(Px-Ux) > 0, or E == 0 and P nudged by
// e * (sx, e * sy) lands on the inner side (sx = -1 only on the last column,
// sy = -1 only on the last row). Because that nudged point is inside the
// rectangle and on no mesh edge, every pixel is owned by exactly one triangle
// of a conforming mesh.
//
// Header-only so the tritree, the interpolation stage and tests share one
// definition. Exact integer arithmetic only; coordinates < 4096 keep every
// product below 2^26.
#pragma once

#include <algorithm>
#include <cstdint>

#include "tristereo/mesh.hpp"

namespace tristereo {

namespace fill_rule_detail {

constexpr std::int64_t floor_div(std::int64_t a, std::int64_t b) {  // b > 0
  return (a >= 0) ? a / b : -((-a + b - 1) / b);
}

// Narrows [x_begin, x_end) to the pixels of row y that edge u -> v owns.
// E(x) = c - dy * x with c = dx (y - uy) + dy ux, so each edge is a half-line
// in x; the tie rule only decides the one pixel where E == 0.
inline void clip_row_by_edge(const Vertex& u, const Vertex& v, int y, int width,
                             int height, std::int64_t& x_begin, std::int64_t& x_end) {
  const std::int64_t dx = v.x - u.x;
  const std::int64_t dy = v.y - u.y;
  const std::int64_t c = dx * (y - u.y) + dy * u.x;
  if (dy == 0) {
    // Horizontal edge: E = c on the whole row; a tie is decided by sy alone.
    const std::int64_t sy = (y == height - 1) ? -1 : 1;
    if (!(c > 0 || (c == 0 && sy * dx > 0))) x_end = x_begin;  // row empty
    return;
  }
  if (dy > 0) {
    // Owned: dy x < c, plus the tie x = c / dy only when it is the last column
    // (sx = -1 there, and -sx dy > 0).
    const std::int64_t t_floor = floor_div(c, dy);
    const bool exact = t_floor * dy == c;
    std::int64_t end = exact ? t_floor : t_floor + 1;  // first x with dy x >= c
    if (exact && t_floor == width - 1) end = width;
    x_end = std::min(x_end, end);
  } else {
    // Owned: |dy| x > -c, plus the tie x = -c / |dy| unless it is the last
    // column (there sx = -1 and -sx dy < 0).
    const std::int64_t q = -dy;
    const std::int64_t t_floor = floor_div(-c, q);
    const bool exact = t_floor * q == -c;
    std::int64_t begin = t_floor + 1;
    if (exact && t_floor != width - 1) begin = t_floor;
    x_begin = std::max(x_begin, begin);
  }
}

// Brute-force edge test, literally the model's rule.
inline bool edge_owns(const Vertex& u, const Vertex& v, int x, int y, int width,
                      int height) {
  const std::int64_t dx = v.x - u.x;
  const std::int64_t dy = v.y - u.y;
  const std::int64_t e = dx * (y - u.y) - dy * (x - u.x);
  if (e != 0) return e > 0;
  const std::int64_t sx = (x == width - 1) ? -1 : 1;
  const std::int64_t sy = (y == height - 1) ? -1 : 1;
  return (-sx * dy > 0) || (dy == 0 && sy * dx > 0);
}

}  // namespace fill_rule_detail

// True when triangle (a, b, c) (area2 > 0) owns pixel (x, y) of a width x height
// image. One pixel at a time, straight from the definition: the oracle for
// for_each_owned_span and for the float reference's own transcription.
inline bool owns_pixel(const Vertex& a, const Vertex& b, const Vertex& c, int x, int y,
                       int width, int height) {
  using fill_rule_detail::edge_owns;
  return edge_owns(a, b, x, y, width, height) && edge_owns(b, c, x, y, width, height) &&
         edge_owns(c, a, x, y, width, height);
}

// Calls fn(y, x_begin, x_end) for each row of (a, b, c) (area2 > 0, vertices
// inside the image) with at least one owned pixel, in increasing y; the owned
// pixels of row y are exactly [x_begin, x_end) (a convex triangle owns a
// contiguous run per row). Cost: O(1) per row, no per-pixel tests.
template <class Fn>
void for_each_owned_span(Vertex a, Vertex b, Vertex c, int width, int height, Fn&& fn) {
  using fill_rule_detail::clip_row_by_edge;
  const int y_lo = std::max(0, std::min({a.y, b.y, c.y}));
  const int y_hi = std::min(height - 1, std::max({a.y, b.y, c.y}));
  for (int y = y_lo; y <= y_hi; ++y) {
    std::int64_t x_begin = 0;
    std::int64_t x_end = width;
    clip_row_by_edge(a, b, y, width, height, x_begin, x_end);
    clip_row_by_edge(b, c, y, width, height, x_begin, x_end);
    clip_row_by_edge(c, a, y, width, height, x_begin, x_end);
    if (x_begin < x_end) fn(y, static_cast<int>(x_begin), static_cast<int>(x_end));
  }
}

}  // namespace tristereo
