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

namespace fill_rule_detail {

constexpr std::int32_t floor_div32(std::int32_t a, std::int32_t b) {  // b > 0
  return (a >= 0) ? a / b : -((-a + b - 1) / b);
}

// clip_row_by_edge for consecutive rows without a division per row. Along an
// edge the boundary is x = num(y) / den with num growing by a constant `step`
// per row, so floor(num / den) and its remainder advance by the fixed
// (floor(step / den), step mod den): two divisions per edge and triangle
// instead of one per row (the divisions dominated the tritree's criterion).
// Every value is an exact integer below 2^26, so int32 suffices.
class EdgeRows {
 public:
  EdgeRows(const Vertex& u, const Vertex& v, int y0) {
    const std::int32_t dx = v.x - u.x;
    const std::int32_t dy = v.y - u.y;
    const std::int32_t c = dx * (y0 - u.y) + dy * u.x;  // E(x) = c - dy x on row y0
    if (dy == 0) {
      kind_ = 0;
      t_ = c;  // E on the whole row
      q_step_ = dx;
      return;
    }
    // dy > 0 bounds x_end by c / dy; dy < 0 bounds x_begin by -c / |dy|.
    kind_ = dy > 0 ? 1 : -1;
    const std::int32_t num = dy > 0 ? c : -c;
    const std::int32_t step = dy > 0 ? dx : -dx;
    den_ = dy > 0 ? dy : -dy;
    if (den_ == 1 || dx == 0) {
      // Edges at 45 degrees (den 1) and vertical ones (num = den * ux, step
      // 0): the quotient is exact without a division.
      if (dx == 0) {
        t_ = u.x;
        rem_ = 0;
        q_step_ = 0;
        r_step_ = 0;
        return;
      }
      t_ = num;
      rem_ = 0;
      q_step_ = step;
      r_step_ = 0;
      return;
    }
    t_ = floor_div32(num, den_);
    rem_ = num - t_ * den_;
    q_step_ = floor_div32(step, den_);
    r_step_ = step - q_step_ * den_;
  }

  // Narrows [x_begin, x_end) exactly as clip_row_by_edge does for the current row.
  void clip(int y, int width, int height, std::int32_t& x_begin, std::int32_t& x_end) const {
    if (kind_ > 0) {
      // First x with dy x >= c; the tie x = c / dy is owned only on the last column.
      const std::int32_t end = (rem_ != 0) ? t_ + 1 : (t_ == width - 1 ? width : t_);
      x_end = std::min(x_end, end);
    } else if (kind_ < 0) {
      // The tie x = -c / |dy| is owned unless it is the last column.
      const std::int32_t begin = (rem_ == 0 && t_ != width - 1) ? t_ : t_ + 1;
      x_begin = std::max(x_begin, begin);
    } else {
      const std::int32_t sy = (y == height - 1) ? -1 : 1;
      if (!(t_ > 0 || (t_ == 0 && sy * q_step_ > 0))) x_end = x_begin;  // row empty
    }
  }

  // Moves to the next row.
  void next_row() {
    t_ += q_step_;
    if (kind_ != 0) {
      rem_ += r_step_;
      if (rem_ >= den_) {
        rem_ -= den_;
        ++t_;
      }
    }
  }

 private:
  int kind_ = 0;
  std::int32_t t_ = 0;       // floor quotient (horizontal edge: E itself)
  std::int32_t rem_ = 0;     // remainder in [0, den_)
  std::int32_t den_ = 1;
  std::int32_t q_step_ = 0;  // per-row quotient step (horizontal edge: dx)
  std::int32_t r_step_ = 0;  // per-row remainder step in [0, den_)
};

}  // namespace fill_rule_detail

// Calls fn(y, x_begin, x_end) for each row of (a, b, c) (area2 > 0, vertices
// inside the image) with at least one owned pixel, in increasing y; the owned
// pixels of row y are exactly [x_begin, x_end) (a convex triangle owns a
// contiguous run per row). Cost: O(1) per row with no division (EdgeRows);
// tests check it against owns_pixel() and clip_row_by_edge() is the per-row
// statement of the same rule.
template <class Fn>
void for_each_owned_span(Vertex a, Vertex b, Vertex c, int width, int height, Fn&& fn) {
  using fill_rule_detail::EdgeRows;
  const int y_lo = std::max(0, std::min({a.y, b.y, c.y}));
  const int y_hi = std::min(height - 1, std::max({a.y, b.y, c.y}));
  EdgeRows ab(a, b, y_lo), bc(b, c, y_lo), ca(c, a, y_lo);
  for (int y = y_lo; y <= y_hi; ++y) {
    std::int32_t x_begin = 0;
    std::int32_t x_end = width;
    ab.clip(y, width, height, x_begin, x_end);
    bc.clip(y, width, height, x_begin, x_end);
    ca.clip(y, width, height, x_begin, x_end);
    if (x_begin < x_end) fn(y, static_cast<int>(x_begin), static_cast<int>(x_end));
    ab.next_row();
    bc.next_row();
    ca.next_row();
  }
}

}  // namespace tristereo
