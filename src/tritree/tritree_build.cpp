// Tritree build: need bottom-up per tile, carried across tile borders, then
// the leaves top-down (docs/tritree.md).
#include <algorithm>
#include <atomic>
#include <cstring>
#include <string>
#include <thread>

#include "platform/clock.hpp"
#include "platform/cpu_relax.hpp"
#include "platform/side_work.hpp"
#include "platform/thread_pool.hpp"
#include "platform/work_chunks.hpp"
#include "src/aggregate/predecessor_offers.hpp"
#include "src/kernels/kernel_set.hpp"
#include "src/tritree/fill_rule.hpp"
#include "src/tritree/rtin_descent.hpp"
#include "src/tritree/side4_shapes.hpp"
#include "src/tritree/side8_shapes.hpp"
#include "src/tritree/tritree.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

namespace {

using rtin_descent::kNeed;

// A grid point's need byte: bit 0 need, bit 2 (value 4) the wants of the
// triangle whose apex comes first in raster order, bit 1 (value 2) the
// other's. By bitwise operations: written with || and ?:, the compiler
// branched on each test's outcome, which no predictor can guess.
inline std::uint8_t need_byte(bool need, bool wants_4, bool wants_2) {
  return static_cast<std::uint8_t>(static_cast<unsigned>(need) | static_cast<unsigned>(wants_4) << 2 |
                                   static_cast<unsigned>(wants_2) << 1);
}

int trailing_zeros(int v, int none) { return v == 0 ? none : __builtin_ctz(static_cast<unsigned>(v)); }

std::int32_t twice_area(const int* x, const int* y) {
  return (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
}

}  // namespace

// ---------------------------------------------------------------- geometry

void Tritree::corners(const Tri& t, int* x, int* y) const {
  const int x0 = t.x0, y0 = t.y0, s = t.s, x1 = t.x0 + s, y1 = t.y0 + s;
  if (t.half) {
    if (RtinLayout::backslash(x0, y0, s)) {
      if (t.part == 0) {  // upper right
        x[0] = x0, y[0] = y0, x[1] = x1, y[1] = y0, x[2] = x1, y[2] = y1;
      } else {            // lower left
        x[0] = x0, y[0] = y0, x[1] = x1, y[1] = y1, x[2] = x0, y[2] = y1;
      }
    } else {
      if (t.part == 0) {  // upper left
        x[0] = x0, y[0] = y0, x[1] = x1, y[1] = y0, x[2] = x0, y[2] = y1;
      } else {            // lower right
        x[0] = x1, y[0] = y0, x[1] = x1, y[1] = y1, x[2] = x0, y[2] = y1;
      }
    }
    return;
  }
  // Side triangle: the side's two corners in clockwise order, then the centre.
  static constexpr int kCx[5] = {0, 1, 1, 0, 0};
  static constexpr int kCy[5] = {0, 0, 1, 1, 0};
  x[0] = kCx[t.part] ? x1 : x0, y[0] = kCy[t.part] ? y1 : y0;
  x[1] = kCx[t.part + 1] ? x1 : x0, y[1] = kCy[t.part + 1] ? y1 : y0;
  x[2] = x0 + s / 2, y[2] = y0 + s / 2;
}

Tritree::Where Tritree::where(const int* x, const int* y) const {
  const int min_x = std::min({x[0], x[1], x[2]}), max_x = std::max({x[0], x[1], x[2]});
  const int min_y = std::min({y[0], y[1], y[2]}), max_y = std::max({y[0], y[1], y[2]});
  if (min_x >= layout_.vw || min_y >= layout_.vh) return Where::kOutside;
  if (max_x <= layout_.vw && max_y <= layout_.vh) return Where::kInside;
  return Where::kCrossing;
}

void Tritree::midpoint(const Tri& t, int* mx, int* my) {
  const int h = t.s / 2;
  if (t.half) {
    *mx = t.x0 + h, *my = t.y0 + h;
    return;
  }
  static constexpr int kMx[4] = {1, 2, 1, 0};  // in half sides, per side
  static constexpr int kMy[4] = {0, 1, 2, 1};
  *mx = t.x0 + kMx[t.part] * h, *my = t.y0 + kMy[t.part] * h;
}

bool Tritree::parent(const Tri& t, Tri* p) const {
  if (!t.half) {
    // The square's half that contains side t.part.
    const bool bs = RtinLayout::backslash(t.x0, t.y0, t.s);
    static constexpr int kHalfBs[4] = {0, 0, 1, 1}, kHalfSlash[4] = {0, 1, 1, 0};
    *p = Tri{true, t.s, t.x0, t.y0, bs ? kHalfBs[t.part] : kHalfSlash[t.part]};
    return true;
  }
  if (t.s == tile_) return false;
  const int qx = (t.x0 / t.s) & 1, qy = (t.y0 / t.s) & 1;
  // Side of the parent square that quadrant (qx, qy)'s half t.part lies on.
  static constexpr int kSide[2][2][2] = {{{0, 3}, {3, 2}}, {{0, 1}, {1, 2}}};  // [qx][qy][part]
  *p = Tri{false, 2 * t.s, t.x0 - qx * t.s, t.y0 - qy * t.s, kSide[qx][qy][t.part]};
  return true;
}

// Bit 1 (value 2) for the triangle whose apex lies after its midpoint in
// raster order (below it, or right of it on the same row), bit 2 for the other.
int Tritree::need_bit(const Tri& t) const {
  if (t.half) return t.part == 1 ? 2 : 4;
  return (t.part == 0 || t.part == 3) ? 2 : 4;  // top / left: the apex (centre) after the midpoint
}

int Tritree::find_tris(int mx, int my, Tri* out) const {
  const int none = 30;
  const int zx = trailing_zeros(mx, none), zy = trailing_zeros(my, none);
  const int k = std::min(zx, zy);
  const int s = 2 << k;
  if (s > tile_) return 0;  // a tile corner
  const int h = s / 2;
  const int ext_x = layout_.tiles_x * tile_, ext_y = layout_.tiles_y * tile_;
  int n = 0;
  if (zx == zy) {
    out[n++] = Tri{true, s, mx - h, my - h, 0};
    out[n++] = Tri{true, s, mx - h, my - h, 1};
  } else if (zx < zy) {  // on a horizontal side
    if (my - s >= 0) out[n++] = Tri{false, s, mx - h, my - s, 2};
    if (my < ext_y) out[n++] = Tri{false, s, mx - h, my, 0};
  } else {               // on a vertical side
    if (mx - s >= 0) out[n++] = Tri{false, s, mx - s, my - h, 1};
    if (mx < ext_x) out[n++] = Tri{false, s, mx, my - h, 3};
  }
  return n;
}

// ---------------------------------------------------------------- the test

// Per span only the image's sums need the pixels; the geometric ones are
// sums of consecutive integers (closed forms), and those with y are the
// row's sums times its y.
PixelMoments Tritree::moments_by_spans(const int* rx, const int* ry, int ox, int oy) const {
  PixelMoments m;
  for_each_owned_span(Vertex{rx[0], ry[0]}, Vertex{rx[1], ry[1]}, Vertex{rx[2], ry[2]}, gray_.width,
                      gray_.height, [&](int y, int x0, int x1) {
                        if (x1 <= x0) return;
                        const std::uint8_t* row = gray_.row(y);
                        std::int32_t si = 0, sxi = 0, sii = 0;
                        for (int x = x0; x < x1; ++x) {
                          const std::int32_t i = row[x];
                          si += i, sxi += (x - ox) * i, sii += i * i;
                        }
                        const std::int32_t n = x1 - x0, a = x0 - ox, b = x1 - 1 - ox, ly = y - oy;
                        // sum of x and of x^2 for x = a .. b
                        const std::int32_t sx = (a + b) * n / 2;
                        // 0^2 + .. + k^2, a polynomial exact for every integer k (F(-1) = 0)
                        const auto sq_to = [](std::int32_t k) { return k * (k + 1) * (2 * k + 1) / 6; };
                        const std::int32_t sxx = sq_to(b) - sq_to(a - 1);
                        m.n += n, m.sx += sx, m.sy += n * ly, m.sxx += sxx, m.sxy += ly * sx, m.syy += n * ly * ly;
                        m.si += si, m.sxi += sxi, m.syi += ly * si, m.sii += sii;
                      });
  return m;
}

bool Tritree::wants_split(const int* rx, const int* ry, const PixelMoments* m, int ox, int oy) const {
  const std::int32_t area2 = twice_area(rx, ry);
  if (area2 > 2 * params_.max_area_px2) return true;
  PlaneCorner c[3];
  for (int i = 0; i < 3; ++i) c[i] = PlaneCorner{rx[i] - ox, ry[i] - oy, gray_.row(ry[i])[rx[i]]};
  return plane_fit_fails(plane_sse(*m, c[0], c[1], c[2]), m->n, area2, mse_q8_);
}

// ---------------------------------------------------------------- pass 1

// The test of a general tile's triangle inside the grid (virtual corners vx,
// vy): a stretched one by the sums of its own pixels (its children do not
// partition it), one larger than A_max without sums, the others from their
// children's sums; m gets the sums it was tested with.
template <class ChildrenSums>
bool Tritree::general_wants(const int* vx, const int* vy, bool moments_needed, int tx0, int ty0,
                            const TileScratch& sc, PixelMoments& m, ChildrenSums children) const {
  int rx[3], ry[3];
  for (int c = 0; c < 3; ++c) rx[c] = layout_.real_x(vx[c]), ry[c] = layout_.real_y(vy[c]);
  if (layout_.stretched(vx[0], vy[0], vx[1], vy[1], vx[2], vy[2])) {
    if (twice_area(rx, ry) > 2 * params_.max_area_px2) return true;
    m = tile_moments_by_spans(rx, ry, tx0, ty0, sc);
    return wants_split(rx, ry, &m, tx0, ty0);
  }
  if (!moments_needed) return true;
  m = children();
  return wants_split(rx, ry, &m, tx0, ty0);
}

// A general tile's square of side s at (x0, y0) (virtual coordinates),
// bottom-up. A square inside the grid and off its last row and column is a
// plain one: tile_plain<s> does all of it (then its halves' intensity sums
// become full sums for the parent); a square wholly outside has nothing;
// the others go triangle by triangle, from their quadrants' halves up.
// out[0..1]: the square's halves' sums relative to the tile origin (tx0,
// ty0), set when the halves are tested.
void Tritree::general_square(int tx0, int ty0, int x0, int y0, int s, const TileScratch& sc, PixelMoments* out) {
  if (x0 >= layout_.vw || y0 >= layout_.vh) return;  // every triangle outside
  const int two_amax = 2 * params_.max_area_px2;
  const int l = __builtin_ctz(static_cast<unsigned>(s)) - 1;  // level: side 2 << l
  if (s >= 4 && x0 + s < layout_.vw && y0 + s < layout_.vh) {
    tile_plain_of_side(s, x0, y0, sc);
    if (s * s <= two_amax) {
      const bool bs = RtinLayout::backslash(x0, y0, s);
      const IntensityMoments* halves = sc.half_i[static_cast<std::size_t>(l)];
      for (int part = 0; part < 2; ++part) {
        const int g = bs ? part : 2 + part;  // half_shape_: '\' upper right, lower left, '/' upper left, lower right
        const int ax = g == 3 ? x0 + s : x0;  // the first corner (corners())
        out[part] = full_moments(halves[part], half_shape_[static_cast<std::size_t>(l)][static_cast<std::size_t>(g)],
                                 x0 - tx0, y0 - ty0, ax - tx0, y0 - ty0);
      }
    }
    return;
  }
  const auto in_grid = [&](int x, int y) { return x <= layout_.vw && y <= layout_.vh; };
  if (s == 2) {
    // The halves of a 2 x 2 square.
    const bool bs = RtinLayout::backslash(x0, y0, 2);
    PixelMoments a, b;
    int rx[2][3], ry[2][3];
    for (int part = 0; part < 2; ++part) {
      int vx[3], vy[3];
      corners(Tri{true, 2, x0, y0, part}, vx, vy);
      for (int c = 0; c < 3; ++c) rx[part][c] = layout_.real_x(vx[c]), ry[part][c] = layout_.real_y(vy[c]);
    }
    if (x0 + 2 < layout_.vw && y0 + 2 < layout_.vh) {
      const std::uint8_t* r0 = gray_.row(y0) + x0;
      const std::uint8_t* r1 = gray_.row(y0 + 1) + x0;
      const int lx = x0 - tx0, ly = y0 - ty0;
      a.add_pixel(lx, ly, r0[0]);
      a.add_pixel(lx + 1, ly, r0[1]);
      if (bs) {
        a.add_pixel(lx + 1, ly + 1, r1[1]);
        b.add_pixel(lx, ly + 1, r1[0]);
      } else {
        a.add_pixel(lx, ly + 1, r1[0]);
        b.add_pixel(lx + 1, ly + 1, r1[1]);
      }
    } else {
      a = tile_moments_by_spans(rx[0], ry[0], tx0, ty0, sc);
      b = tile_moments_by_spans(rx[1], ry[1], tx0, ty0, sc);
    }
    out[0] = a;
    out[1] = b;
    const bool may_want = params_.min_area_px2 <= 1;  // virtual area 2 px^2
    const bool wa = may_want && wants_split(rx[0], ry[0], &a, tx0, ty0);
    const bool wb = may_want && wants_split(rx[1], ry[1], &b, tx0, ty0);
    cell(x0 + 1, y0 + 1) |= need_byte(wa | wb, wa, wb);
    return;
  }
  const int h = s / 2;
  // The quadrants' halves: quad[(dy * 2 + dx) * 2 + part].
  PixelMoments quad[8];
  for (int dy = 0; dy < 2; ++dy)
    for (int dx = 0; dx < 2; ++dx) general_square(tx0, ty0, x0 + dx * h, y0 + dy * h, h, sc, quad + (dy * 2 + dx) * 2);
  // Side triangle k = the halves of two of the quadrants: {quadrant dx, dy, half} x 2.
  static constexpr int kQuad[4][2][3] = {{{0, 0, 0}, {1, 0, 0}},   // top: TL.A + TR.A
                                         {{1, 0, 1}, {1, 1, 0}},   // right: TR.B + BR.A
                                         {{1, 1, 1}, {0, 1, 1}},   // bottom: BR.B + BL.B
                                         {{0, 1, 0}, {0, 0, 1}}};  // left: BL.A + TL.B
  const bool moments_needed = s * s / 2 <= two_amax;  // side triangles: area2 = s^2 / 2
  // Below twice the minimum area the test is made for the sums alone.
  const bool sides_may_want = s * s / 2 >= 4 * params_.min_area_px2;
  const bool halves_may_want = s * s >= 4 * params_.min_area_px2;
  PixelMoments sides[4];
  for (int k = 0; k < 4; ++k) {
    const Tri t{false, s, x0, y0, k};
    int vx[3], vy[3];
    corners(t, vx, vy);
    int mx, my;
    midpoint(t, &mx, &my);
    const Where w = where(vx, vy);
    if (w == Where::kOutside) continue;
    if (w == Where::kCrossing) {
      if (in_grid(mx, my)) cell(mx, my) |= kNeed;
      continue;
    }
    const auto& q0 = kQuad[k][0];
    const auto& q1 = kQuad[k][1];
    const bool wants = general_wants(vx, vy, moments_needed, tx0, ty0, sc, sides[k], [&] {
      return quad[(q0[1] * 2 + q0[0]) * 2 + q0[2]] + quad[(q1[1] * 2 + q1[0]) * 2 + q1[2]];
    }) && sides_may_want;
    // Children: the halves of two quadrants, whose midpoints are the quadrant centres.
    const int cx0 = x0 + kQuad[k][0][0] * h + h / 2, cy0 = y0 + kQuad[k][0][1] * h + h / 2;
    const int cx1 = x0 + kQuad[k][1][0] * h + h / 2, cy1 = y0 + kQuad[k][1][1] * h + h / 2;
    const bool own = wants | ((cell(cx0, cy0) | cell(cx1, cy1)) & kNeed);
    cell(mx, my) |= static_cast<std::uint8_t>(static_cast<unsigned>(own) | (wants ? need_bit(t) : 0));
  }
  const bool half_moments_needed = s * s <= two_amax;
  const bool bs = RtinLayout::backslash(x0, y0, s);
  for (int part = 0; part < 2; ++part) {
    const Tri t{true, s, x0, y0, part};
    int vx[3], vy[3];
    corners(t, vx, vy);
    const int mx = x0 + h, my = y0 + h;
    const Where w = where(vx, vy);
    if (w == Where::kOutside) continue;
    if (w == Where::kCrossing) {
      if (in_grid(mx, my)) cell(mx, my) |= kNeed;
      continue;
    }
    // The half's two side triangles: '\' part 0 = top + right, part 1 =
    // bottom + left; '/' part 0 = top + left, part 1 = right + bottom.
    const int k0 = part == 0 ? 0 : (bs ? 2 : 1);
    const int k1 = part == 0 ? (bs ? 1 : 3) : (bs ? 3 : 2);
    const bool wants =
        general_wants(vx, vy, half_moments_needed, tx0, ty0, sc, out[part], [&] { return sides[k0] + sides[k1]; }) &&
        halves_may_want;
    int ax, ay, bx, by;
    midpoint(Tri{false, s, x0, y0, k0}, &ax, &ay);
    midpoint(Tri{false, s, x0, y0, k1}, &bx, &by);
    const bool own = wants | ((cell(ax, ay) | cell(bx, by)) & kNeed);
    cell(mx, my) |= static_cast<std::uint8_t>(static_cast<unsigned>(own) | (wants ? need_bit(t) : 0));
  }
}

// general_square() finishes each square before the next: a half read the
// need of its side midpoints before the square beside it (plain or not)
// added its own side triangle's. Those midpoints lie on the squares'
// sides, on lines x or y = 0 mod 4 (the squares of side 2 have no side
// midpoint their halves read), so carrying up every need on those lines
// inside the tile (the tile's own border is pass 2's, as for plain tiles)
// gives the need the level-by-level order gives: the least set closed
// under "a child's midpoint needs, so does its parent's".
void Tritree::carry_inside_tile(int tx0, int ty0) {
  const int x1 = std::min(tx0 + tile_, layout_.vw + 1), y1 = std::min(ty0 + tile_, layout_.vh + 1);
  for (int y = ty0 + 1; y < y1; ++y) {
    const int step = (y & 3) == 0 ? 1 : 4;
    for (int x = (y & 3) == 0 ? tx0 + 1 : tx0 + 4; x < x1; x += step)
      if (cell(x, y) & kNeed) carry_up(x, y);
  }
}

// A plain square's halves' sums from its intensity sums (relative to its own
// corner, o = its corner - the tile origin) and its shape (relative to the
// first corner, a = that corner - the tile origin).
PixelMoments Tritree::full_moments(const IntensityMoments& mi, const ShapeMoments& g, int ox, int oy, int ax, int ay) {
  PixelMoments m;
  m.n = g.n;
  m.sx = g.sx + ax * g.n;
  m.sy = g.sy + ay * g.n;
  m.sxx = g.sxx + 2 * ax * g.sx + ax * ax * g.n;
  m.sxy = g.sxy + ax * g.sy + ay * g.sx + ax * ay * g.n;
  m.syy = g.syy + 2 * ay * g.sy + ay * ay * g.n;
  m.si = mi.si;
  m.sxi = mi.sxi + ox * mi.si;
  m.syi = mi.syi + oy * mi.si;
  m.sii = mi.sii;
  return m;
}

// A plain tile (inside the virtual grid, away from its last row and column:
// nothing crossing, stretched or on the image border), or such a square of a
// general tile (general_square): the same tests as general_square's, with
// the side S known at compile time (so the levels unroll and every shape's
// u and v are constants). Its 2 x 2 squares own their top-left 2 x 2 pixels; a half of
// area 2 px^2 owns a corner and edge or hypotenuse midpoints only, whose
// residuals are closed forms.
// The side-2 level when its halves are not tested: each 2 x 2 square's two
// halves' intensity sums (relative to the tile origin), for the level above.
// '\\' squares: A = upper right owns (0,0) (1,0) (1,1), B = lower left
// (0,1); '/' squares: A = upper left owns (0,0) (1,0) (0,1), B = lower right
// (1,1). Along a row of squares the two alternate.
template <int S>
void Tritree::side2_sums_only(int tx0, int ty0, const TileScratch& sc) const {
  constexpr int n = S / 2;  // even: S >= 4
  const std::uint8_t* img = gray_.data;
  const std::ptrdiff_t istride = gray_.stride_bytes;
  IntensityMoments* out = sc.half_i[0];
  const auto square = [&](auto backslash, const std::uint8_t* r0, const std::uint8_t* r1, int i, std::int32_t ly,
                          IntensityMoments* o) {
    constexpr bool bs = decltype(backslash)::value;
    const int x = tx0 + 2 * i;
    const std::int32_t lx = 2 * i;
    const std::int32_t i00 = r0[x], i10 = r0[x + 1];
    const std::int32_t pa = bs ? r1[x + 1] : r1[x];  // A's third pixel
    const std::int32_t pb = bs ? r1[x] : r1[x + 1];  // B's pixel
    constexpr int ax = bs ? 1 : 0, bx = bs ? 0 : 1;
    const std::int32_t top_i = i00 + i10;
    o[0] = IntensityMoments{top_i + pa, lx * top_i + i10 + (lx + ax) * pa, ly * top_i + (ly + 1) * pa,
                            i00 * i00 + i10 * i10 + pa * pa};
    o[1] = IntensityMoments{pb, (lx + bx) * pb, (ly + 1) * pb, pb * pb};
  };
  for (int j = 0; j < n; ++j) {
    const int y = ty0 + 2 * j;
    const std::uint8_t* r0 = img + y * istride;
    const std::uint8_t* r1 = r0 + istride;
    const std::int32_t ly = 2 * j;
    IntensityMoments* o = out + 2 * n * j;
    if ((((tx0 >> 1) + (y >> 1)) & 1) == 0) {
      for (int i = 0; i < n; i += 2) {
        square(std::true_type{}, r0, r1, i, ly, o + 2 * i);
        square(std::false_type{}, r0, r1, i + 1, ly, o + 2 * i + 2);
      }
    } else {
      for (int i = 0; i < n; i += 2) {
        square(std::false_type{}, r0, r1, i, ly, o + 2 * i);
        square(std::true_type{}, r0, r1, i + 1, ly, o + 2 * i + 2);
      }
    }
  }
}

template <int S>
void Tritree::tile_plain(int tx0, int ty0, const TileScratch& sc, bool side4_ready) {
  if constexpr (S >= 8) {
    if (side4_ready) {  // the side-4 level is in the band buffers (side4_band)
      if constexpr (S >= 16) {
        if (side8_kernel_) {  // and the side-8 level (side8_band)
          apply_kernel_level<S, 4>(tx0, ty0, sc.side4_wants, sc.side4_sums, side4_stride_, nullptr);
          apply_kernel_level<S, 8>(tx0, ty0, sc.side8_wants, sc.side8_sums, side8_stride_, sc.half_i[2]);
          plain_level<S, 16>(tx0, ty0, sc);
          return;
        }
      }
      apply_kernel_level<S, 4>(tx0, ty0, sc.side4_wants, sc.side4_sums, side4_stride_, sc.half_i[1]);
      plain_level<S, 8>(tx0, ty0, sc);
      return;
    }
  }
  const int two_amax = 2 * params_.max_area_px2;
  const std::size_t stride = static_cast<std::size_t>(layout_.vw) + 1;
  std::uint8_t* need = need_;
  const std::uint8_t* img = gray_.data;
  const std::ptrdiff_t istride = gray_.stride_bytes;
  const std::uint64_t mse = mse_q8_;

  // Side 2. Its halves (virtual area 2 px^2) want to split only with a
  // minimum area of 1 px^2; otherwise only their sums are needed (the
  // defaults): then the need stays as cleared and the halves' orientation,
  // alternating along a row, is a template argument instead of selects.
  if (S >= 4 && 4 <= two_amax && params_.min_area_px2 > 1) {
    side2_sums_only<S>(tx0, ty0, sc);
  } else {
    const bool test = 4 <= two_amax && params_.min_area_px2 <= 1;
    const bool keep_moments = S >= 4 && 8 <= two_amax;  // the side triangles of side 4 are tested
    constexpr int n = S / 2;
    IntensityMoments* out = sc.half_i[0];
    for (int j = 0; j < n; ++j) {
      const int y = ty0 + 2 * j;
      const std::uint8_t* r0 = img + y * istride;
      const std::uint8_t* r1 = r0 + istride;
      const std::uint8_t* r2 = r1 + istride;
      std::uint8_t* need_row = need + (static_cast<std::size_t>(y) + 1) * stride;
      const std::int32_t ly = 2 * j;
      for (int i = 0; i < n; ++i, out += 2) {
        const int x = tx0 + 2 * i;
        const std::int32_t i00 = r0[x], i10 = r0[x + 1], i20 = r0[x + 2];
        const std::int32_t i01 = r1[x], i11 = r1[x + 1];
        const std::int32_t i02 = r2[x], i22 = r2[x + 2];
        const bool bs = (((x >> 1) + (y >> 1)) & 1) == 0;
        // Untested: larger than A_max (wants), or below the minimum area (does not).
        bool wa = two_amax < 4, wb = two_amax < 4;
        const std::int32_t e_top = 2 * i10 - i00 - i20, e_left = 2 * i01 - i00 - i02;
        if (test) {
          // Residuals are area2 (= 4) times the error against the mean of the
          // two corners the pixel lies between: 2 e.
          std::uint64_t sse_a, sse_b;
          if (bs) {  // A = upper right owns (0,0) (1,0) (1,1); B = lower left owns (0,1)
            const std::int32_t e_diag = 2 * i11 - i00 - i22;
            sse_a = 4u * static_cast<std::uint64_t>(e_top * e_top + e_diag * e_diag);
            sse_b = 4u * static_cast<std::uint64_t>(e_left * e_left);
          } else {   // A = upper left owns (0,0) (1,0) (0,1); B = lower right owns (1,1)
            const std::int32_t e_diag = 2 * i11 - i20 - i02;
            sse_a = 4u * static_cast<std::uint64_t>(e_top * e_top + e_left * e_left);
            sse_b = 4u * static_cast<std::uint64_t>(e_diag * e_diag);
          }
          wa = plane_fit_fails(sse_a, 3, 4, mse);
          wb = plane_fit_fails(sse_b, 1, 4, mse);
        }
        need_row[x + 1] = need_byte(wa | wb, wa, wb);
        if (keep_moments) {
          // The square's four pixels; A takes three, B the fourth.
          const std::int32_t lx = 2 * i;
          const std::int32_t top_i = i00 + i10, top_ii = i00 * i00 + i10 * i10;
          IntensityMoments a{top_i, lx * top_i + i10, ly * top_i, top_ii};
          const std::int32_t px = bs ? lx : lx + 1;          // B's pixel
          const std::int32_t pb = bs ? i01 : i11, pa = bs ? i11 : i01;  // and A's third
          const std::int32_t ax = bs ? lx + 1 : lx;
          a.si += pa, a.sxi += ax * pa, a.syi += (ly + 1) * pa, a.sii += pa * pa;
          out[0] = a;
          out[1] = IntensityMoments{pb, px * pb, (ly + 1) * pb, pb * pb};
        }
      }
    }
  }
  if constexpr (S >= 4) plain_level<S, 4>(tx0, ty0, sc);
}

namespace {

// The plane test of a plain tile's triangle of shape g (u = B - A = (kUx,
// kUy), v = C - A = (kVx, kVy)) with first corner (xa, ya).
template <int kUx, int kUy, int kVx, int kVy>
inline bool fixed_shape_fails(const IntensityMoments& m, const ShapeMoments& g, const std::uint8_t* img,
                              std::ptrdiff_t istride, int tx0, int ty0, int xa, int ya) {
  const std::int32_t ia = img[ya * istride + xa];
  const std::int32_t ib = img[(ya + kUy) * istride + xa + kUx];
  const std::int32_t ic = img[(ya + kVy) * istride + xa + kVx];
  return plane_sse_of_fixed_shape<kUx, kUy, kVx, kVy>(m, g, xa - tx0, ya - ty0, ia, ib, ic) * 256 >
         g.fail_above_q8;
}

constexpr int log2_of(int v) { return v <= 1 ? 0 : 1 + log2_of(v / 2); }

}  // namespace

// Level s (4 .. S) of a plain tile: the side triangles of its squares (from
// their quadrants' halves), then the squares' halves; then level 2 s.
template <int S, int s>
void Tritree::plain_level(int tx0, int ty0, const TileScratch& sc) {
  constexpr int h = s / 2, n = S / s, qn = 2 * n, l = log2_of(s) - 1;
  const int two_amax = 2 * params_.max_area_px2;
  const std::size_t stride = static_cast<std::size_t>(layout_.vw) + 1;
  std::uint8_t* need = need_;
  const std::uint8_t* img = gray_.data;
  const std::ptrdiff_t istride = gray_.stride_bytes;
  constexpr std::int32_t side_area2 = s * s / 2, half_area2 = s * s;
  const bool test_sides = side_area2 <= two_amax;
  const bool test_halves = half_area2 <= two_amax;
  // Below twice the minimum area a triangle does not want to split (its sums
  // are still made: the level above needs them). Never so above A_max
  // (largest_min_area_px2).
  const bool sides_may_want = side_area2 >= 4 * params_.min_area_px2;
  const bool halves_may_want = half_area2 >= 4 * params_.min_area_px2;
  const std::array<ShapeMoments, 4>& side_g = side_shape_[l];
  const std::array<ShapeMoments, 4>& half_g = half_shape_[l];
  const IntensityMoments* quads = sc.half_i[l - 1];
  IntensityMoments* halves = sc.half_i[l];
  IntensityMoments* sides = sc.side_i;
  const auto q = [&](int i, int j, int dx, int dy, int part) -> const IntensityMoments& {
    return quads[((2 * j + dy) * qn + 2 * i + dx) * 2 + part];
  };
  const auto at = [&](int x, int y) -> std::uint8_t& { return need[static_cast<std::size_t>(y) * stride + x]; };
  // Side triangles: need at the side midpoints.
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const int x0 = tx0 + i * s, y0 = ty0 + j * s, x1 = x0 + s, y1 = y0 + s, cx = x0 + h, cy = y0 + h;
      const int qx0 = x0 + h / 2, qx1 = cx + h / 2, qy0 = y0 + h / 2, qy1 = cy + h / 2;  // quadrant centres
      const bool nq00 = at(qx0, qy0) & kNeed, nq10 = at(qx1, qy0) & kNeed;
      const bool nq01 = at(qx0, qy1) & kNeed, nq11 = at(qx1, qy1) & kNeed;
      bool w[4] = {true, true, true, true};
      if (test_sides) {
        IntensityMoments* m = sides + (j * n + i) * 4;
        m[0] = q(i, j, 0, 0, 0) + q(i, j, 1, 0, 0);
        m[1] = q(i, j, 1, 0, 1) + q(i, j, 1, 1, 0);
        m[2] = q(i, j, 1, 1, 1) + q(i, j, 0, 1, 1);
        m[3] = q(i, j, 0, 1, 0) + q(i, j, 0, 0, 1);
        // Corners in clockwise order from A, then the centre (corners()).
        if (sides_may_want) {
          w[0] = fixed_shape_fails<s, 0, h, h>(m[0], side_g[0], img, istride, tx0, ty0, x0, y0);
          w[1] = fixed_shape_fails<0, s, -h, h>(m[1], side_g[1], img, istride, tx0, ty0, x1, y0);
          w[2] = fixed_shape_fails<-s, 0, -h, -h>(m[2], side_g[2], img, istride, tx0, ty0, x1, y1);
          w[3] = fixed_shape_fails<0, -s, h, -h>(m[3], side_g[3], img, istride, tx0, ty0, x0, y1);
        } else {
          w[0] = w[1] = w[2] = w[3] = false;
        }
      }
      at(cx, y0) |= need_byte(w[0] | nq00 | nq10, false, w[0]);
      at(x1, cy) |= need_byte(w[1] | nq10 | nq11, w[1], false);
      at(cx, y1) |= need_byte(w[2] | nq11 | nq01, w[2], false);
      at(x0, cy) |= need_byte(w[3] | nq01 | nq00, false, w[3]);
    }
  }
  // Halves: need at the centres (the sides' sums are only kept when the
  // halves are tested, which implies the sides were).
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const int x0 = tx0 + i * s, y0 = ty0 + j * s, x1 = x0 + s, y1 = y0 + s, cx = x0 + h, cy = y0 + h;
      const bool bs = RtinLayout::backslash(x0, y0, s);
      const bool n_top = at(cx, y0) & kNeed, n_right = at(x1, cy) & kNeed;
      const bool n_bottom = at(cx, y1) & kNeed, n_left = at(x0, cy) & kNeed;
      bool wa = true, wb = true;
      if (test_halves) {
        const IntensityMoments* m = sides + (j * n + i) * 4;
        IntensityMoments* out = halves + (j * n + i) * 2;
        out[0] = m[0] + (bs ? m[1] : m[3]);
        out[1] = bs ? m[2] + m[3] : m[1] + m[2];
        if (!halves_may_want) {
          wa = wb = false;
        } else if (bs) {
          wa = fixed_shape_fails<s, 0, s, s>(out[0], half_g[0], img, istride, tx0, ty0, x0, y0);
          wb = fixed_shape_fails<s, s, 0, s>(out[1], half_g[1], img, istride, tx0, ty0, x0, y0);
        } else {
          wa = fixed_shape_fails<s, 0, 0, s>(out[0], half_g[2], img, istride, tx0, ty0, x0, y0);
          wb = fixed_shape_fails<0, s, -s, s>(out[1], half_g[3], img, istride, tx0, ty0, x1, y0);
        }
      }
      const bool own_a = wa | n_top | (bs ? n_right : n_left);
      const bool own_b = wb | n_bottom | (bs ? n_left : n_right);
      at(cx, cy) |= need_byte(own_a | own_b, wa, wb);
    }
  }
  if constexpr (2 * s <= S) plain_level<S, 2 * s>(tx0, ty0, sc);
}

void Tritree::tile_plain_of_side(int side, int tx0, int ty0, const TileScratch& sc, bool side4_ready) {
  switch (side) {
    case 2: tile_plain<2>(tx0, ty0, sc, false); break;
    case 4: tile_plain<4>(tx0, ty0, sc, false); break;
    case 8: tile_plain<8>(tx0, ty0, sc, side4_ready); break;
    case 16: tile_plain<16>(tx0, ty0, sc, side4_ready); break;
    case 32: tile_plain<32>(tx0, ty0, sc, side4_ready); break;
    default: tile_plain<64>(tx0, ty0, sc, side4_ready); break;  // A_max <= 1024: S <= 64
  }
}

// The side-4 level of a row of tiles' plain tiles (the first plain_tiles of
// the row, at ty0), row of squares by row of squares: every 4 x 4 square's
// tests and its halves' sums, by the kernel (KernelSet::side4_tests_u8)
// along the whole run of tiles. Its rows reach the squares' lower corners
// (ty0 + S < vh) and its last column their right ones (plain_tiles S < vw).
void Tritree::side4_band(int ty0, int plain_tiles, const TileScratch& sc) const {
  const int n = plain_tiles * (tile_ / 4);
  for (int j = 0; j < tile_ / 4; ++j) {
    const int y = ty0 + 4 * j;
    const std::uint8_t* rows[5];
    for (int r = 0; r < 5; ++r) rows[r] = gray_.row(y + r);
    kernels_->side4_tests_u8(rows, n, RtinLayout::backslash(0, y, 4), side4_limit_.data(),
                             sc.side4_wants + static_cast<std::size_t>(j) * side4_stride_,
                             sc.side4_sums + static_cast<std::size_t>(j) * 8 * side4_stride_, side4_stride_);
  }
}

// The side-8 level of a row of tiles' plain tiles, row of squares by row of
// squares, from side4_band's sums: every 8 x 8 square's tests and its
// halves' sums, by the kernel (KernelSet::side8_tests_s32) along the whole
// run of tiles.
void Tritree::side8_band(int ty0, int plain_tiles, const TileScratch& sc) const {
  const int n = plain_tiles * (tile_ / 8);
  for (int j = 0; j < tile_ / 8; ++j) {
    const int y = ty0 + 8 * j;
    const std::uint8_t* rows[3] = {gray_.row(y), gray_.row(y + 4), gray_.row(y + 8)};
    const std::int32_t* quad_sums[2] = {sc.side4_sums + static_cast<std::size_t>(2 * j) * 8 * side4_stride_,
                                        sc.side4_sums + static_cast<std::size_t>(2 * j + 1) * 8 * side4_stride_};
    kernels_->side8_tests_s32(quad_sums, side4_stride_, rows, n, RtinLayout::backslash(0, y, 8), side8_limit_.data(),
                              sc.side8_wants + static_cast<std::size_t>(j) * side8_stride_,
                              sc.side8_sums + static_cast<std::size_t>(j) * 8 * side8_stride_, side8_stride_);
  }
}

// plain_level<S, s> (s = 4, 8) from a kernel's results along the row of
// tiles (side4_band, side8_band: per row of squares, wants bits and 8 sums
// planes with stride ss): the same need bytes, and the halves' sums
// relative to the tile origin (when `halves` is not null: the side-8 kernel
// reads side 4's from the band buffers), the tests already made. At s = 4
// no need lies at the quadrants' centres (the 2 x 2 squares are untested).
template <int S, int s>
void Tritree::apply_kernel_level(int tx0, int ty0, const std::uint32_t* wants_rows, const std::int32_t* sums_rows,
                                 std::size_t ss, IntensityMoments* halves) {
  static_assert(side4::kWantsHalfBit == side8::kWantsHalfBit, "one layout of the wants bits");
  constexpr int n = S / s, h = s / 2;
  const std::size_t stride = static_cast<std::size_t>(layout_.vw) + 1;
  std::uint8_t* need = need_;
  const auto at = [&](int x, int y) -> std::uint8_t& { return need[static_cast<std::size_t>(y) * stride + x]; };
  const int m0 = tx0 / s;  // the tile's first square in the band's rows
  for (int j = 0; j < n; ++j) {
    const std::uint32_t* wants = wants_rows + static_cast<std::size_t>(j) * ss + m0;
    for (int i = 0; i < n; ++i) {
      const int x0 = tx0 + s * i, y0 = ty0 + s * j, x1 = x0 + s, y1 = y0 + s, cx = x0 + h, cy = y0 + h;
      bool nq00 = false, nq10 = false, nq01 = false, nq11 = false;  // quadrant centres
      if constexpr (s > 4) {
        nq00 = at(x0 + h / 2, y0 + h / 2) & kNeed, nq10 = at(cx + h / 2, y0 + h / 2) & kNeed;
        nq01 = at(x0 + h / 2, cy + h / 2) & kNeed, nq11 = at(cx + h / 2, cy + h / 2) & kNeed;
      }
      const std::uint32_t b = wants[i];
      const bool w0 = b & 1u, w1 = (b >> 1) & 1u, w2 = (b >> 2) & 1u, w3 = (b >> 3) & 1u;
      at(cx, y0) |= need_byte(w0 | nq00 | nq10, false, w0);
      at(x1, cy) |= need_byte(w1 | nq10 | nq11, w1, false);
      at(cx, y1) |= need_byte(w2 | nq11 | nq01, w2, false);
      at(x0, cy) |= need_byte(w3 | nq01 | nq00, false, w3);
    }
  }
  for (int j = 0; j < n; ++j) {
    const std::uint32_t* wants = wants_rows + static_cast<std::size_t>(j) * ss + m0;
    const std::int32_t* sums = sums_rows + static_cast<std::size_t>(j) * 8 * ss + m0;
    for (int i = 0; i < n; ++i) {
      const int x0 = tx0 + s * i, y0 = ty0 + s * j, x1 = x0 + s, y1 = y0 + s, cx = x0 + h, cy = y0 + h;
      const bool bs = RtinLayout::backslash(x0, y0, s);
      const bool n_top = at(cx, y0) & kNeed, n_right = at(x1, cy) & kNeed;
      const bool n_bottom = at(cx, y1) & kNeed, n_left = at(x0, cy) & kNeed;
      const std::uint32_t b = wants[i] >> side4::kWantsHalfBit;
      const bool wa = b & 1u, wb = (b >> 1) & 1u;
      if (halves != nullptr) {
        IntensityMoments* out = halves + (j * n + i) * 2;
        const std::int32_t ox = x0 - tx0, oy = y0 - ty0;
        for (int p = 0; p < 2; ++p) {
          const std::int32_t* sp = sums + static_cast<std::size_t>(4 * p) * ss + i;
          const std::int32_t si = sp[0];
          out[p] = IntensityMoments{si, ox * si + sp[ss], oy * si + sp[2 * ss], sp[3 * ss]};
        }
      }
      const bool own_a = wa | n_top | (bs ? n_right : n_left);
      const bool own_b = wb | n_bottom | (bs ? n_left : n_right);
      at(cx, cy) |= need_byte(own_a | own_b, wa, wb);
    }
  }
}

// ---------------------------------------------------------------- pass 2

// need(m) of a midpoint on a tile border holds both tiles' parts only once
// both tiles are done; whatever it adds is carried up to the parents.
// A border midpoint (x, y) of a square of side 2h is a side triangle's, whose
// parents are the halves of the squares on either side of the border: their
// midpoints are those squares' centres, h away across it. Mostly both are
// set already (by their own tiles), and the whole carry_up() is skipped.
// The borders of rows of tiles [ty0, ty1): the horizontal one on top of each
// and the vertical ones inside (the grid's last row with the last row of
// tiles). Rows of tiles go to different workers at once: a carry may climb
// into any tile near its border, so the need bytes are read and set by
// atomic operations here. The result does not depend on the order: it is
// the closure of the need bits under the carry (a bit, once set, is carried
// up by the one worker that set it).
void Tritree::carry_across_tile_borders(int ty0, int ty1) {
  const int S = tile_, vw = layout_.vw, vh = layout_.vh;
  const std::size_t stride = static_cast<std::size_t>(vw) + 1;
  const auto need_at = [&](int x, int y) {
    return (__atomic_load_n(need_ + static_cast<std::size_t>(y) * stride + x, __ATOMIC_RELAXED) & kNeed) != 0;
  };
  const int y_end = ty1 == layout_.tiles_y ? vh + 1 : std::min(ty1 * S, vh + 1);
  for (int y = ty0 * S; y < y_end; ++y) {
    if (y % S == 0) {  // a horizontal border: parents above and below
      for (int x = 0; x <= vw; ++x) {
        if (!need_at(x, y)) continue;
        const int h = x & -x;  // x = 0 or h >= S: a tile corner, no triangle
        if (h == 0 || h >= S) continue;
        if ((y < h || need_at(x, y - h)) && (y + h > vh || need_at(x, y + h))) continue;
        carry_up(x, y);
      }
    } else {  // vertical borders: parents left and right
      const int h = y & -y;
      for (int x = 0; x <= vw; x += S) {
        if (!need_at(x, y)) continue;
        if ((x < h || need_at(x - h, y)) && (x + h > vw || need_at(x + h, y))) continue;
        carry_up(x, y);
      }
    }
  }
}

void Tritree::carry_up(int x, int y) {
  Tri tris[2];
  const int n = find_tris(x, y, tris);
  for (int i = 0; i < n; ++i) {
    Tri p;
    if (!parent(tris[i], &p)) continue;
    int px, py;
    midpoint(p, &px, &py);
    // Mostly the parent's need is already set (by its own tile): test that first.
    if (px > layout_.vw || py > layout_.vh || (__atomic_load_n(&cell(px, py), __ATOMIC_RELAXED) & kNeed)) continue;
    int vx[3], vy[3];
    corners(tris[i], vx, vy);
    if (where(vx, vy) != Where::kInside) continue;
    corners(p, vx, vy);
    if (where(vx, vy) != Where::kInside) continue;  // crossing parents need anyway
    // Another worker may have set it meanwhile: then that one carries it up.
    if (__atomic_fetch_or(&cell(px, py), kNeed, __ATOMIC_RELAXED) & kNeed) continue;
    carry_up(px, py);
  }
}

// ---------------------------------------------------------------- pass 3

namespace {

using rtin_descent::emit_rtin;
using rtin_descent::PlainEmit;

// A plain tile's half with apex offset (kDx, kDy) from the tile centre (mx, my).
template <int kSlots, int kDx, int kDy>
inline void emit_plain_half(PlainEmit& e, const std::uint8_t* need, const std::int32_t* ids, int mx, int my) {
  const auto at = [](std::size_t stride, int x, int y) {
    return static_cast<std::size_t>(y) * stride + static_cast<std::size_t>(x);
  };
  emit_rtin<kSlots, kDx, kDy>(e, need + at(e.need_stride, mx, my), ids + at(e.id_stride, mx, my),
                      ids[at(e.id_stride, mx - kDy, my + kDx)], ids[at(e.id_stride, mx + kDy, my - kDx)],
                      ids[at(e.id_stride, mx + kDx, my + kDy)]);
}

// Both halves of a plain tile of side S at x = tx0, hypotenuse first; `need`
// and `ids` point at the tile's first row (of the need grid, of the row of
// tiles' ids).
template <int kSlots, int S>
inline void emit_plain_halves(PlainEmit& e, const std::uint8_t* need, const std::int32_t* ids, int tx0,
                              bool backslash) {
  constexpr int h = S / 2;
  const int mx = tx0 + h, my = h;
  if (backslash) {
    emit_plain_half<kSlots, h, -h>(e, need, ids, mx, my);  // upper right
    emit_plain_half<kSlots, -h, h>(e, need, ids, mx, my);  // lower left
  } else {
    emit_plain_half<kSlots, -h, -h>(e, need, ids, mx, my);  // upper left
    emit_plain_half<kSlots, h, h>(e, need, ids, mx, my);    // lower right
  }
}

}  // namespace

// A plain tile: the descent for its tile side (and the predecessor slots per vertex).
template <int kSlots>
void Tritree::emit_plain_tile(Band& b, int tx0, int ty0) {
  PlainEmit e{static_cast<std::size_t>(layout_.vw) + 1, static_cast<std::size_t>(gray_.width), b.leaves + b.count,
              0, 0, pred_keys_, vertices_, tx0 == 0};
  const bool bs = RtinLayout::backslash(tx0, ty0, tile_);
  // A plain tile is off the moved last row: its rows are the ids' first ones.
  const std::uint8_t* need = need_ + static_cast<std::size_t>(ty0) * e.need_stride;
  switch (tile_) {
    case 2: emit_plain_halves<kSlots, 2>(e, need, b.ids, tx0, bs); break;
    case 4: emit_plain_halves<kSlots, 4>(e, need, b.ids, tx0, bs); break;
    case 8: emit_plain_halves<kSlots, 8>(e, need, b.ids, tx0, bs); break;
    case 16: emit_plain_halves<kSlots, 16>(e, need, b.ids, tx0, bs); break;
    case 32: emit_plain_halves<kSlots, 32>(e, need, b.ids, tx0, bs); break;
    default: emit_plain_halves<kSlots, 64>(e, need, b.ids, tx0, bs); break;  // A_max <= 1024: S <= 64
  }
  b.count = static_cast<std::size_t>(e.out - b.leaves);
  b.criterion += e.criterion;
  b.forced += e.forced;
}

void Tritree::emit_tile(Band& b, int tx0, int ty0, bool plain) {
  const int S = tile_;
  const int x1 = tx0 + S, y1 = ty0 + S;
  // Hypotenuse first; (a, b, c) keeps the positive orientation of the halves.
  if (plain) {
    switch (pred_slots_) {
      case 0: emit_plain_tile<0>(b, tx0, ty0); break;
      case 2: emit_plain_tile<2>(b, tx0, ty0); break;
      default: emit_plain_tile<6>(b, tx0, ty0); break;
    }
  } else if (RtinLayout::backslash(tx0, ty0, S)) {
    emit(b, x1, y1, tx0, ty0, x1, ty0);   // upper right
    emit(b, tx0, ty0, x1, y1, tx0, y1);   // lower left
  } else {
    emit(b, x1, ty0, tx0, y1, tx0, ty0);  // upper left
    emit(b, tx0, y1, x1, ty0, x1, y1);    // lower right
  }
}

// ---------------------------------------------------------------- build

// The predecessor table is complete once the general tiles have offered
// theirs; its reach is bounded by the ids of each row of tiles' rows
// (with the next one's first): every edge lies inside one row of tiles.
void Tritree::finish_predecessors(const Mesh& mesh, PredecessorTable* preds) const {
  int reach = 0;
  preds->bounds = PredecessorBounds{};
  for (int band = 0; band < layout_.tiles_y; ++band) {
    preds->bounds.merge(bands_[band].bounds);
    const int y0 = layout_.real_y(band * tile_), y1 = layout_.real_y(std::min((band + 1) * tile_, layout_.vh));
    reach = std::max(reach, mesh.row_start[static_cast<std::size_t>(y1) + 1] - mesh.row_start[static_cast<std::size_t>(y0)] - 1);
  }
  preds->reach = reach;
  preds->filled = true;
}

TritreeGrid Tritree::grid() const {
  TritreeGrid g;
  g.layout = layout_;
  g.need = layout_.strip() ? nullptr : need_;
  g.stretched = stretched_;
  g.stretched_count = stretched_count_;
  g.band_start = band_start_;
  return g;
}

void Tritree::build(ImageView<const std::uint8_t> gray, Mesh& mesh, ThreadPool* pool, PredecessorTable* preds,
                    SideWork* side) {
  validate_image(gray);
  if (preds != nullptr && preds->directions != 4 && preds->directions != 8)
    throw Error(ErrorCode::kInvalidArgument, "tritree: predecessor table for " + std::to_string(preds->directions) +
                                                 " directions (4 or 8)");
  if (preds != nullptr) preds->filled = false;
  pred_slots_ = preds != nullptr ? preds->directions - 2 : 0;
  pred_keys_ = preds != nullptr ? reinterpret_cast<std::uint32_t*>(preds->slots) : nullptr;
  const std::int64_t t0 = monotonic_ns();
  gray_ = gray;
  layout_ = RtinLayout(gray.width, gray.height, params_.max_area_px2);
  criterion_splits_ = forced_splits_ = 0;
  stretched_count_ = 0;

  // The serial steps, with the side work beside them on the other workers.
  const auto serial = [&](auto step) {
    if (side != nullptr)
      side->beside(pool, step);
    else
      step();
  };
  if (layout_.strip()) {
    times_.criterion_ns = 0;
  } else {
    for (TileScratch& sc : scratch_) {  // the span records hold for one image size
      SpanCache& c = *sc.spans;
      if (c.width == gray.width && c.height == gray.height) continue;
      c.width = gray.width;
      c.height = gray.height;
      for (SpanKind& k : c.kinds) k.recorded = k.unusable = false;
    }
    const int S = tile_;
    // Each row of tiles clears the need grid's rows it is the first to touch
    // right before its tiles: no serial memset of the whole grid.
    const auto clear_need_rows = [&](int vy0, int vy1) {
      const auto row_len = static_cast<std::size_t>(layout_.vw) + 1;
      if (vy1 >= vy0)
        std::memset(need_ + static_cast<std::size_t>(vy0) * row_len, 0, static_cast<std::size_t>(vy1 - vy0 + 1) * row_len);
    };
    const auto tile_row = [&](int ty, const TileScratch& sc, bool clear_top, bool clear_bottom) {
      // Its closed rows of the grid: the top one shared with the row of tiles
      // above, the bottom one with the one below (or the grid's last).
      const int top = ty * S, bottom = std::min((ty + 1) * S, layout_.vh);
      clear_need_rows(clear_top ? top : top + 1, clear_bottom ? bottom : bottom - 1);
      // Plain tiles: x0 + S < vw and y0 + S < vh, the row's first (vw - 1) / S.
      const int plain_tiles = ty * S + S < layout_.vh ? (layout_.vw - 1) / S : 0;
      const bool side4 = side4_kernel_ && plain_tiles > 0;
      if (side4) side4_band(ty * S, plain_tiles, sc);
      if (side4 && side8_kernel_) side8_band(ty * S, plain_tiles, sc);
      for (int tx = 0; tx < layout_.tiles_x; ++tx) {
        const int x0 = tx * S, y0 = ty * S;
        if (x0 + S < layout_.vw && y0 + S < layout_.vh) {
          tile_plain_of_side(S, x0, y0, sc, side4);
        } else {
          PixelMoments halves[2];
          begin_span_tile(sc, tx, ty);
          general_square(x0, y0, x0, y0, S, sc, halves);
          end_span_tile(sc);
          carry_inside_tile(x0, y0);
        }
      }
    };
    // A tile reads and writes only the grid points of its own closed square,
    // so rows of tiles two apart never touch the same byte.
    // A row of tiles as a work item of the trace: phase 0 the criterion, 1
    // the numbering and emission.
    const auto traced = [this](int w, int phase, int ty, auto&& work) {
      const std::int64_t b = trace_ != nullptr ? monotonic_ns() : 0;
      work();
      if (trace_ != nullptr) trace_->record(w, TraceKind::kTritreeRows, b, monotonic_ns(), phase, ty);
    };
    const int workers = pool != nullptr ? std::min(pool->size(), kMaxTileWorkers) : 1;
    if (workers > 1 && layout_.tiles_y > 2) {
      // Rows taken as workers come free (a fixed deal left one worker two
      // rows more, or the slow general last row on top), from the bottom up
      // so that the last row, all general tiles, goes first: the last row's
      // parity first, then the other's. A row of the second parity shares
      // grid points with its two neighbours only, and waits for those alone,
      // not for the whole first parity (the barrier between the parities left
      // a worker idle for up to a row). A worker takes the lowest second-parity
      // row not yet taken whose neighbours are done, and waits only when there
      // is none: with a fixed order it waited behind a neighbour whose worker
      // another process had preempted, for a time slice (the tritree went
      // below 1x on two loaded cores).
      // row_done_: 0 not taken, 1 under way, 2 done.
      const int tiles_y = layout_.tiles_y;
      const int first = (tiles_y + 1) / 2;  // rows of the last row's parity
      for (int ty = 0; ty < tiles_y; ++ty) row_done_[ty].store(0, std::memory_order_relaxed);
      std::atomic<int> next{0};
      pool->run([&](int w) {
        if (w >= workers) return;
        // The first parity clears its closed rows, the second (whose
        // neighbours did its top and bottom rows) its rows between, and
        // the grid's first row when it is the first row of tiles.
        for (int k = next.fetch_add(1, std::memory_order_relaxed); k < first;
             k = next.fetch_add(1, std::memory_order_relaxed)) {
          const int ty = tiles_y - 1 - 2 * k;
          traced(w, 0, ty, [&] { tile_row(ty, scratch_[w], true, true); });
          row_done_[ty].store(2, std::memory_order_release);
        }
        const auto done = [&](int r) {
          return r < 0 || r >= tiles_y || row_done_[r].load(std::memory_order_acquire) == 2;
        };
        for (int spins = 0;;) {
          int ty = -1;
          bool left = false;
          for (int r = tiles_y - 2; r >= 0 && ty < 0; r -= 2) {
            if (row_done_[r].load(std::memory_order_relaxed) != 0) continue;
            left = true;
            std::uint8_t free_row = 0;
            if (done(r - 1) && done(r + 1) &&
                row_done_[r].compare_exchange_strong(free_row, 1, std::memory_order_acq_rel))
              ty = r;
          }
          if (ty < 0) {
            if (!left) break;
            // With more workers than CPUs the neighbour's worker may need this CPU.
            cpu_relax();
            if (++spins >= 4096) std::this_thread::yield();
            continue;
          }
          spins = 0;
          traced(w, 0, ty, [&] { tile_row(ty, scratch_[w], ty == 0, false); });
          row_done_[ty].store(2, std::memory_order_release);
        }
      });
    } else {
      // In order: each row of tiles clears its rows but the first (the row
      // above's last), the first row of tiles that one too.
      for (int ty = 0; ty < layout_.tiles_y; ++ty)
        traced(0, 0, ty, [&] { tile_row(ty, scratch_[0], ty == 0, true); });
    }
    // The carry across tile borders, rows of tiles on demand (trace phase 2).
    if (workers > 1) {
      WorkChunks border_rows;
      border_rows.reset(0, layout_.tiles_y, 1);
      pool->run([&](int w) {
        int t0 = 0, t1 = 0;
        while (border_rows.next(&t0, &t1)) traced(w, 2, t0, [&] { carry_across_tile_borders(t0, t1); });
      });
    } else {
      for (int ty = 0; ty < layout_.tiles_y; ++ty) traced(0, 2, ty, [&] { carry_across_tile_borders(ty, ty + 1); });
    }
    const std::int64_t t1 = monotonic_ns();
    times_.criterion_ns = t1 - t0;
    begin_mesh(mesh);
    // Also counts each row of tiles' leaves.
    const std::size_t leaves = count_vertices(mesh, workers > 1 ? pool : nullptr);
    vertices_ = mesh.vertices.data();
    // Each row of tiles numbers its vertices, then writes its leaves straight
    // into their place in the mesh, tiles left to right: the plain ones by the
    // fixed-shape descent, then the general ones (the last column's, or all of
    // the last row's) by emit(). Its leaves reach the next one's first row,
    // which that one numbers: on a pool, rows go from the last one up (to the
    // workers as they come free: the last row, all general tiles, is the
    // slowest), and each waits for the one below to be numbered.
    mesh.triangles.resize(leaves);  // within capacity
    for (int ty = 0; ty < layout_.tiles_y; ++ty) {
      bands_[ty] = Band{};
      bands_[ty].leaves = mesh.triangles.data() + band_start_[ty];
      bands_[ty].stretched = stretched_ + static_cast<std::size_t>(ty) * stretched_per_band_;
      row_done_[ty].store(0, std::memory_order_relaxed);
    }
    const auto number = [&](int ty, std::int32_t* ids) {
      number_band(ty, mesh, ids, bands_[ty]);
      row_done_[ty].store(1, std::memory_order_release);
    };
    const auto emit_band = [&](int ty) {
      Band b = bands_[ty];  // a local copy: neighbouring rows' Bands share cache lines
      if (ty + 1 < layout_.tiles_y) {
        // A short wait: the row below was taken before this one.
        for (int spins = 0; row_done_[ty + 1].load(std::memory_order_acquire) == 0; ++spins) {
          cpu_relax();
          if (spins >= 4096) std::this_thread::yield();
        }
        next_first_row_ids(ty, mesh, b);
      }
      if (pred_slots_ > 0) empty_band_slots(ty, mesh);
      for (int tx = 0; tx < layout_.tiles_x; ++tx) {
        const int x0 = tx * S, y0 = ty * S;
        const bool plain = x0 + S < layout_.vw && y0 + S < layout_.vh;
        emit_tile(b, x0, y0, plain);
      }
      if (pred_slots_ > 0) {
        offer_stretched(b);
        band_predecessor_bounds(ty, mesh, b);
      }
      bands_[ty] = b;
    };
    if (workers > 1) {
      std::atomic<int> next{0};
      pool->run([&](int w) {
        if (w >= workers) return;  // each has its rows of ids
        for (int ty = layout_.tiles_y - 1 - next.fetch_add(1, std::memory_order_relaxed); ty >= 0;
             ty = layout_.tiles_y - 1 - next.fetch_add(1, std::memory_order_relaxed)) {
          traced(w, 1, ty, [&] {
            number(ty, scratch_[static_cast<std::size_t>(w)].band_ids);
            emit_band(ty);
          });
        }
      });
    } else {
      // In order, each row numbered one ahead (into the other of two sets of
      // rows of ids), so that the mesh is written front to back.
      const auto ids = [&](int ty) { return scratch_[static_cast<std::size_t>(ty & 1)].band_ids; };
      number(0, ids(0));
      for (int ty = 0; ty < layout_.tiles_y; ++ty) {
        traced(0, 1, ty, [&] {
          if (ty + 1 < layout_.tiles_y) number(ty + 1, ids(ty + 1));
          emit_band(ty);
        });
      }
    }
    serial([&] {
      collect_stretched();
      if (pred_slots_ > 0) finish_predecessors(mesh, preds);
    });
  }
  finish(mesh);
  times_.output_ns = monotonic_ns() - t0 - times_.criterion_ns;
}

}  // namespace tristereo
