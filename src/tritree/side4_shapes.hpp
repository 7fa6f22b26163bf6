// The side-4 level of a plain tile, pixel by pixel (docs/tritree.md, "The
// side-4 level"): which of a 4 x 4 square's triangles owns each of its 16
// pixels, and the plane through each triangle's corners as integer weights.
// Shared by the scalar kernel (side4_tests_scalar.cpp) and its SIMD twins.
//
// A square's 16 pixels split among its four side triangles (centre to a side)
// as the fill rule gives them: its 2 x 2 quadrants alternate diagonals ('\' at
// (0,0) and (2,2), '/' at (2,0) and (0,2)) whatever the square's own diagonal,
// and each side triangle owns the halves of the two quadrants along its side.
// A half of the square owns the pixels of the two side triangles it contains.
//
// For a triangle A, B, C with twice its area a2 = (B - A) x (C - A) and a pixel
// P, a2 times the plane's value at P is wA IA + wB IB + wC IC with integer
// weights (a2 times P's barycentric coordinates), so the model's residual
// (docs/model.md section 1) is r = a2 IP - (wA IA + wB IB + wC IC): small
// integers (|r| <= a2 * 255, the plane at an owned pixel being between its
// corners' intensities), and SSE = sum of r^2 over the owned pixels is exact
// in int32 (at most 8 pixels * (16 * 255)^2 < 2^27).
#pragma once

#include <array>
#include <cstdint>

namespace tristereo {
namespace side4 {

// The corners a square's triangles use, and where they are.
enum Corner { kTopLeft, kTopRight, kBottomLeft, kBottomRight, kCentre, kCorners };
constexpr int kCornerX[kCorners] = {0, 4, 0, 4, 2};
constexpr int kCornerY[kCorners] = {0, 0, 4, 4, 2};

struct Tri {
  int a, b, c;  // corners, in the order Tritree::corners() lists them
};
// Side triangles: top, right, bottom, left (the side's corners clockwise, then the centre).
constexpr Tri kSide[4] = {{kTopLeft, kTopRight, kCentre},
                          {kTopRight, kBottomRight, kCentre},
                          {kBottomRight, kBottomLeft, kCentre},
                          {kBottomLeft, kTopLeft, kCentre}};
// Halves [diagonal][part]: '\' upper right, lower left; '/' upper left, lower right.
constexpr Tri kHalf[2][2] = {{{kTopLeft, kTopRight, kBottomRight}, {kTopLeft, kBottomRight, kBottomLeft}},
                             {{kTopLeft, kTopRight, kBottomLeft}, {kTopRight, kBottomRight, kBottomLeft}}};

// The side triangle owning pixel p = 4 dy + dx.
constexpr int kSideOf[16] = {0, 0, 0, 0,  //
                             3, 0, 0, 1,  //
                             3, 3, 1, 1,  //
                             3, 2, 2, 1};

// The half (0: along the top side, 1: the other) owning side triangle `side`'s
// pixels, for a '\' (diagonal 0) or '/' (diagonal 1) square.
constexpr int half_of(int diagonal, int side) {
  return diagonal == 0 ? (side <= 1 ? 0 : 1) : (side == 0 || side == 3 ? 0 : 1);
}

struct PlaneWeights {
  int a2 = 0;                     // twice the triangle's area
  int w[kCorners] = {0, 0, 0, 0, 0};  // per corner; 0 for corners not its own
};

constexpr PlaneWeights plane_weights(const Tri& t, int px, int py) {
  const int ax = kCornerX[t.a], ay = kCornerY[t.a];
  const int ux = kCornerX[t.b] - ax, uy = kCornerY[t.b] - ay;
  const int vx = kCornerX[t.c] - ax, vy = kCornerY[t.c] - ay;
  const int qx = px - ax, qy = py - ay;
  PlaneWeights r;
  r.a2 = ux * vy - uy * vx;
  const int wb = qx * vy - qy * vx, wc = ux * qy - uy * qx;
  r.w[t.a] += r.a2 - wb - wc;
  r.w[t.b] += wb;
  r.w[t.c] += wc;
  return r;
}

// Pixel p's weights in its side triangle, and in its half of a square of each diagonal.
constexpr PlaneWeights side_weights(int p) { return plane_weights(kSide[kSideOf[p]], p & 3, p >> 2); }
constexpr PlaneWeights half_weights(int diagonal, int p) {
  return plane_weights(kHalf[diagonal][half_of(diagonal, kSideOf[p])], p & 3, p >> 2);
}

// sse_limit[] layout of the kernel (KernelSet::side4_tests_u8): the four side
// triangles, then the halves of a '\' square, then those of a '/' square.
constexpr int kLimitSide = 0, kLimitHalf = 4, kLimits = 8;
// wants bits: side triangle k at bit k, half p at bit 4 + p.
constexpr int kWantsHalfBit = 4;

}  // namespace side4
}  // namespace tristereo
