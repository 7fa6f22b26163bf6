// The side-8 level of a plain tile (docs/tritree.md, "The side-8 level"): an
// 8 x 8 square's triangles as compile-time shapes, and their test from the
// intensity sums of its quadrants' halves (the side-4 level's output).
// Shared by the scalar kernel (side8_tests_scalar.cpp) and its SIMD twins.
//
// A side triangle of the square is the halves of two of its 4 x 4 quadrants
// (Tritree::plain_level's table, kQuad below), a half of the square two of its
// side triangles. For a triangle with first corner A, edges u = B - A, v = C -
// A (a2 = u x v) and corner intensities ia, ib, ic, the model's SSE is
//   nx^2 Sx'x' + 2 nx ny Sx'y' + ny^2 Sy'y' + 2 a2 (nx Sx'J + ny Sy'J) + a2^2 SJJ
// (pixel_moments.hpp, plane_sse_with_edges), with (nx, ny) from u, v and
// ib - ia, ic - ia, the geometric sums S.. of the shape (constants here) and
// the image's sums relative to A, J = I - ia. Every term and partial sum is an
// integer below 2^37 for a triangle of at most 32 pixels of this size, so the
// SIMD twins compute it exactly in double precision (53-bit mantissa).
#pragma once

#include <cstdint>

#include "src/tritree/side4_shapes.hpp"

namespace tristereo {
namespace side8 {

enum Corner { kTopLeft, kTopRight, kBottomLeft, kBottomRight, kCentre, kCorners };
constexpr int kCornerX[kCorners] = {0, 8, 0, 8, 4};
constexpr int kCornerY[kCorners] = {0, 0, 8, 8, 4};

// Side triangle k (top, right, bottom, left): quadrant (dx, dy)'s half `part`
// twice, {dx, dy, part}.
constexpr int kQuad[4][2][3] = {{{0, 0, 0}, {1, 0, 0}},
                                {{1, 0, 1}, {1, 1, 0}},
                                {{1, 1, 1}, {0, 1, 1}},
                                {{0, 1, 0}, {0, 0, 1}}};
// Half `part` of a '\' (diagonal 0) or '/' (1) square: two side triangles.
constexpr int kHalfSides[2][2][2] = {{{0, 1}, {2, 3}}, {{0, 3}, {1, 2}}};

// A triangle: its corners (in Tritree::corners() order) and the geometric
// sums of its owned pixels P relative to A: n, x', y', x'^2, x'y', y'^2.
struct Shape {
  int a = 0, b = 0, c = 0;
  int ax = 0, ay = 0, ux = 0, uy = 0, vx = 0, vy = 0, a2 = 0;
  int n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
};

// The side triangle owning pixel (x, y) of the square: its quadrant's
// diagonal is '\' when the quadrant is on the square's diagonal (whatever the
// square's own), and the quadrant's half owning the pixel is side4's.
constexpr int side_of(int x, int y) {
  const int qx = x / 4, qy = y / 4;
  const int part = side4::half_of(qx == qy ? 0 : 1, side4::kSideOf[4 * (y % 4) + x % 4]);
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 2; ++j)
      if (kQuad[k][j][0] == qx && kQuad[k][j][1] == qy && kQuad[k][j][2] == part) return k;
  return -1;
}

// The shape with corners a, b, c owning the pixels of side triangles
// `sides` (a bit per side).
constexpr Shape make_shape(int a, int b, int c, int sides) {
  Shape s;
  s.a = a, s.b = b, s.c = c;
  s.ax = kCornerX[a], s.ay = kCornerY[a];
  s.ux = kCornerX[b] - s.ax, s.uy = kCornerY[b] - s.ay;
  s.vx = kCornerX[c] - s.ax, s.vy = kCornerY[c] - s.ay;
  s.a2 = s.ux * s.vy - s.uy * s.vx;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      if (((sides >> side_of(x, y)) & 1) == 0) continue;
      const int dx = x - s.ax, dy = y - s.ay;
      s.n += 1, s.sx += dx, s.sy += dy, s.sxx += dx * dx, s.sxy += dx * dy, s.syy += dy * dy;
    }
  return s;
}

// Side triangles: the side's corners clockwise, then the centre.
constexpr Shape kSide[4] = {make_shape(kTopLeft, kTopRight, kCentre, 1),
                            make_shape(kTopRight, kBottomRight, kCentre, 2),
                            make_shape(kBottomRight, kBottomLeft, kCentre, 4),
                            make_shape(kBottomLeft, kTopLeft, kCentre, 8)};
// Halves [diagonal][part]: '\' upper right, lower left; '/' upper left, lower right.
constexpr Shape kHalf[2][2] = {
    {make_shape(kTopLeft, kTopRight, kBottomRight, 1 | 2), make_shape(kTopLeft, kBottomRight, kBottomLeft, 4 | 8)},
    {make_shape(kTopLeft, kTopRight, kBottomLeft, 1 | 8), make_shape(kTopRight, kBottomRight, kBottomLeft, 2 | 4)}};
static_assert(kSide[0].n + kSide[1].n + kSide[2].n + kSide[3].n == 64, "the sides partition the square");
static_assert(kHalf[0][0].a2 == 64 && kHalf[1][1].a2 == 64 && kSide[3].a2 == 32, "positive orientation");

// The model's SSE of shape g from the image's sums over its pixels relative to
// the square's corner (m: I, xI, yI, II) and the square's corner intensities.
// Exact in int64 (every term < 2^37).
constexpr std::int64_t sse(const Shape& g, const std::int64_t* m, const std::int32_t* corner) {
  const std::int64_t ia = corner[g.a], ui = corner[g.b] - ia, vi = corner[g.c] - ia;
  const std::int64_t nx = g.uy * vi - ui * g.vy, ny = ui * g.vx - g.ux * vi;
  const std::int64_t sxj = m[1] - g.ax * m[0] - ia * g.sx;
  const std::int64_t syj = m[2] - g.ay * m[0] - ia * g.sy;
  const std::int64_t sjj = m[3] - 2 * ia * m[0] + g.n * ia * ia;
  return nx * nx * g.sxx + 2 * nx * ny * g.sxy + ny * ny * g.syy + 2 * g.a2 * (nx * sxj + ny * syj) +
         std::int64_t{g.a2} * g.a2 * sjj;
}

// sse_limit[] layout of the kernel (KernelSet::side8_tests_s32), as side4's:
// the four side triangles, then the halves of a '\' square, then a '/' one's.
constexpr int kLimitSide = 0, kLimitHalf = 4, kLimits = 8;
constexpr int kWantsHalfBit = 4;  // wants bits: side k at bit k, half p at bit 4 + p

}  // namespace side8
}  // namespace tristereo
