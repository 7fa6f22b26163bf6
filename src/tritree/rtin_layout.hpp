// Where the tritree's right triangles lie (docs/model.md section 1, "Layout").
//
// The hierarchy lives on a *virtual* grid of even size vw x vh: vw = W - 1 when
// that is even, else W - 2 (same for vh). The virtual point (X, Y) is the pixel
// (real_x(X), real_y(Y)): itself, except that the last virtual column (row) is
// moved one pixel right (down) when W - 1 (H - 1) is odd. So every midpoint is
// an exact grid point, and the stretched border triangles still have integer
// corners with area >= their virtual area.
//
// The grid is cut into aligned tiles of side S = 2^k (tile_side_for()); each
// square of side s (a tile, or a quadrant of a square of side 2s) is split by
// its diagonal, '\' when X0/s + Y0/s is even, else '/', so that the diagonal of
// a quadrant always passes through its parent's centre (the RTIN of a square).
// Header-only: the tritree, its tests and the benchmarks share it; the float
// reference keeps its own transcription.
#pragma once

#include <cstdint>

namespace tristereo {

// Smallest power of two S >= 2 whose tile halves (area S^2 / 2) are larger
// than max_area_px2: those always split, so nothing above a tile is ever needed.
constexpr int tile_side_for(int max_area_px2) {
  int s = 2;
  while (s * s / 2 <= max_area_px2) s *= 2;
  return s;
}

struct RtinLayout {
  int width = 0, height = 0;  // the image
  int vw = 0, vh = 0;         // virtual extent (even; 0 when the side is 2 pixels)
  bool stretch_x = false, stretch_y = false;
  int tile = 2;               // tile side S
  int tiles_x = 0, tiles_y = 0;

  RtinLayout() = default;
  RtinLayout(int w, int h, int max_area_px2)
      : width(w), height(h),
        vw((w - 1) & ~1), vh((h - 1) & ~1),
        stretch_x(((w - 1) & 1) != 0), stretch_y(((h - 1) & 1) != 0),
        tile(tile_side_for(max_area_px2)),
        tiles_x((vw + tile - 1) / tile), tiles_y((vh + tile - 1) / tile) {}

  // An image with a side of 2 pixels has no virtual area: its mesh is the two
  // triangles of the diagonal (0,0)-(W-1,H-1), which never split.
  bool strip() const { return vw == 0 || vh == 0; }
  int real_x(int X) const { return X + ((stretch_x && X == vw) ? 1 : 0); }
  int real_y(int Y) const { return Y + ((stretch_y && Y == vh) ? 1 : 0); }
  // True when a triangle with these virtual corners is stretched: its real
  // corners are not its virtual ones moved alike (some, not all, on a moved line).
  bool stretched(int x0, int y0, int x1, int y1, int x2, int y2) const {
    const int cx = (x0 == vw) + (x1 == vw) + (x2 == vw);
    const int cy = (y0 == vh) + (y1 == vh) + (y2 == vh);
    return (stretch_x && cx != 0 && cx != 3) || (stretch_y && cy != 0 && cy != 3);
  }
  // '\' diagonal (from (X0,Y0) to (X0+s,Y0+s)) for the square of side s at (X0, Y0).
  // That is ((X0 / s + Y0 / s) & 1) == 0: for X0, Y0 >= 0 and s a power of
  // two, X0 / s is odd exactly when bit s of X0 is set (no division; the
  // general tiles' runtime s made it an idiv).
  static bool backslash(int x0, int y0, int s) { return ((x0 ^ y0) & s) == 0; }
};

}  // namespace tristereo
