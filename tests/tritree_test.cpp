// Tests of the integer tritree (src/tritree), its fill rule, pixel moments and
// the PSNR threshold: exact known answers and the mesh invariants of
// docs/model.md section 1. Equality with the float reference is in tritree_reference_test.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <set>
#include <utility>
#include <vector>

#include "platform/thread_pool.hpp"
#include "src/model/psnr_threshold.hpp"
#include "src/tritree/fill_rule.hpp"
#include "src/tritree/pixel_moments.hpp"
#include "src/kernels/kernels_scalar.hpp"
#include "src/tritree/rtin_layout.hpp"
#include "src/tritree/side4_shapes.hpp"
#include "src/tritree/side8_shapes.hpp"
#include "src/tritree/tritree.hpp"
#include "support/alloc_counter.hpp"
#include "support/scenes.hpp"
#include "tristereo/gray.hpp"
#include "tristereo/status.hpp"
#include "tristereo/synth.hpp"

namespace tristereo {
namespace {

using test::Rng;

std::int64_t area2_of(const Vertex& a, const Vertex& b, const Vertex& c) {
  return static_cast<std::int64_t>(b.x - a.x) * (c.y - a.y) -
         static_cast<std::int64_t>(b.y - a.y) * (c.x - a.x);
}

ImageView<const std::uint8_t> cview(const ImageU8& img) { return img.view(); }

Mesh build_mesh(const ImageU8& gray, const TritreeParams& params, Tritree* tree_out = nullptr) {
  Tritree local;
  Tritree& tree = tree_out ? *tree_out : local;
  tree.configure(gray.width, gray.height, params);
  Mesh mesh;
  tree.reserve(mesh);
  tree.build(cview(gray), mesh);
  return mesh;
}

// Smooth gradient + noise + a step, all clamped to 0..255.
ImageU8 mixed_image(Rng& rng, int w, int h) {
  ImageU8 img(w, h);
  const int gx = rng.uniform(-6, 6), gy = rng.uniform(-6, 6), noise = rng.uniform(0, 20);
  const int step_x = rng.uniform(0, w), step = rng.uniform(-120, 120);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      int v = 128 + gx * (x - w / 2) + gy * (y - h / 2) + (x >= step_x ? step : 0);
      if (noise > 0) v += rng.uniform(-noise, noise);
      img.at(x, y) = static_cast<std::uint8_t>(std::clamp(v, 0, 255));
    }
  }
  return img;
}

// ------------------------------------------------------------ PSNR threshold

TEST(PsnrThreshold, CommittedStepConstantRegenerates) {
  const long double step = std::pow(10.0L, -0.01L) * 2147483648.0L;
  EXPECT_EQ(static_cast<std::uint64_t>(std::llround(step)), kPsnrStepQ31);
}

TEST(PsnrThreshold, MatchesPowForEveryTenthDb) {
  // The integer result is the definition; this only checks it is the rounded
  // real value up to the Q31 power's tiny error.
  for (int d = kMinPsnrDeciDb; d <= kMaxPsnrDeciDb; ++d) {
    const long double exact = 256.0L * 65025.0L * std::pow(10.0L, -d / 100.0L);
    const long double got = static_cast<long double>(mse_threshold_q8(d));
    EXPECT_LE(std::fabs(got - exact), 0.5L + 1e-6L * exact) << "psnr_deci_db " << d;
  }
  EXPECT_EQ(mse_threshold_q8(0), 16646400u);   // 0 dB: full scale, exactly
  EXPECT_EQ(mse_threshold_q8(400), 1665u);     // 1664.64
  EXPECT_EQ(mse_threshold_q8(700), 2u);        // 1.66
}

// ------------------------------------------------------------ fill rule

TEST(FillRule, SpansEqualBruteForceOnRandomTriangles) {
  Rng rng(11);
  int checked = 0;
  for (int it = 0; it < 20000; ++it) {
    const int w = rng.uniform(2, 24), h = rng.uniform(2, 24);
    Vertex v[3];
    for (Vertex& p : v) p = Vertex{rng.uniform(0, w - 1), rng.uniform(0, h - 1)};
    const std::int64_t a2 = area2_of(v[0], v[1], v[2]);
    if (a2 == 0) continue;
    if (a2 < 0) std::swap(v[1], v[2]);
    std::vector<char> by_span(static_cast<std::size_t>(w) * h, 0);
    int last_y = -1;
    for_each_owned_span(v[0], v[1], v[2], w, h, [&](int y, int x0, int x1) {
      ASSERT_GT(y, last_y);
      ASSERT_LT(x0, x1);
      ASSERT_GE(x0, 0);
      ASSERT_LE(x1, w);
      last_y = y;
      for (int x = x0; x < x1; ++x) by_span[static_cast<std::size_t>(y) * w + x] = 1;
    });
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        ASSERT_EQ(by_span[static_cast<std::size_t>(y) * w + x] != 0,
                  owns_pixel(v[0], v[1], v[2], x, y, w, h))
            << "triangle (" << v[0].x << "," << v[0].y << ") (" << v[1].x << "," << v[1].y
            << ") (" << v[2].x << "," << v[2].y << ") pixel " << x << "," << y;
      }
    }
    ++checked;
  }
  EXPECT_GT(checked, 15000);
}

TEST(FillRule, TwoRootsOfA2x2ImageShareItsPixels) {
  // Roots (0,0),(1,0),(1,1) (above the diagonal, y < x) and (0,0),(1,1),(0,1).
  // The diagonal pixels are decided by the nudge: (0,0) moves to (e, e^2),
  // above the diagonal; (1,1) moves to (1-e, 1-e^2), below it.
  const Vertex a{0, 0}, b{1, 0}, c{1, 1}, d{0, 1};
  EXPECT_TRUE(owns_pixel(a, b, c, 0, 0, 2, 2));
  EXPECT_TRUE(owns_pixel(a, b, c, 1, 0, 2, 2));
  EXPECT_FALSE(owns_pixel(a, b, c, 1, 1, 2, 2));
  EXPECT_FALSE(owns_pixel(a, b, c, 0, 1, 2, 2));
  EXPECT_FALSE(owns_pixel(a, c, d, 0, 0, 2, 2));
  EXPECT_FALSE(owns_pixel(a, c, d, 1, 0, 2, 2));
  EXPECT_TRUE(owns_pixel(a, c, d, 1, 1, 2, 2));
  EXPECT_TRUE(owns_pixel(a, c, d, 0, 1, 2, 2));
}

// ------------------------------------------------------------ layout

TEST(RtinLayout, TileSideAndVirtualGrid) {
  EXPECT_EQ(tile_side_for(1), 2);     // halves of 2 px^2 > 1
  EXPECT_EQ(tile_side_for(2), 4);
  EXPECT_EQ(tile_side_for(100), 16);  // 128 > 100 >= 32
  EXPECT_EQ(tile_side_for(127), 16);
  EXPECT_EQ(tile_side_for(128), 32);
  EXPECT_EQ(tile_side_for(kMaxAreaLimitPx2), 64);
  const RtinLayout teddy(450, 375, 100);  // W-1 = 449 odd, H-1 = 374 even
  EXPECT_EQ(teddy.vw, 448);
  EXPECT_EQ(teddy.vh, 374);
  EXPECT_TRUE(teddy.stretch_x);
  EXPECT_FALSE(teddy.stretch_y);
  EXPECT_EQ(teddy.real_x(448), 449);
  EXPECT_EQ(teddy.real_x(447), 447);
  EXPECT_EQ(teddy.real_y(374), 374);
  EXPECT_EQ(teddy.tiles_x, 28);
  EXPECT_EQ(teddy.tiles_y, 24);  // the last row of tiles is partial
  EXPECT_TRUE(RtinLayout(2, 9, 100).strip());
  EXPECT_FALSE(RtinLayout(3, 3, 100).strip());
  // A quadrant's diagonal passes through its parent's centre.
  EXPECT_TRUE(RtinLayout::backslash(0, 0, 8));   // top-left of (0,0,16): ends at (8,8)
  EXPECT_FALSE(RtinLayout::backslash(8, 0, 8));  // top-right: from (16,0) to (8,8)
  EXPECT_FALSE(RtinLayout::backslash(0, 8, 8));
  EXPECT_TRUE(RtinLayout::backslash(8, 8, 8));
  // The bit test against the definition, (X0 / s + Y0 / s) even.
  for (int s = 2; s <= 64; s *= 2)
    for (int y = 0; y < 300; ++y)
      for (int x = 0; x < 300; ++x)
        ASSERT_EQ(RtinLayout::backslash(x, y, s), ((x / s + y / s) & 1) == 0) << x << "," << y << " s " << s;
}

// ------------------------------------------------------------ pixel moments

// An owned pixel lies in the closed triangle (every edge function >= 0), so
// the brute-force sums need only its bounding box: a whole-image scan per leaf
// made the Middlebury invariants test minutes long under qemu and ASan.
struct Box {
  int x0, y0, x1, y1;
};
Box box_of(const ImageU8& img, Vertex a, Vertex b, Vertex c) {
  return Box{std::max(0, std::min({a.x, b.x, c.x})), std::max(0, std::min({a.y, b.y, c.y})),
             std::min(img.width - 1, std::max({a.x, b.x, c.x})),
             std::min(img.height - 1, std::max({a.y, b.y, c.y}))};
}

// The model's SSE, straight from the definition: pixels by the fill rule,
// residual r = n_x (x - Ax) + n_y (y - Ay) + area2 (I - I_A).
std::uint64_t sse_brute_force(const ImageU8& img, Vertex a, Vertex b, Vertex c, std::int64_t* n_px) {
  const std::int64_t ia = img.at(a.x, a.y), ib = img.at(b.x, b.y), ic = img.at(c.x, c.y);
  const std::int64_t ux = b.x - a.x, uy = b.y - a.y, ui = ib - ia;
  const std::int64_t vx = c.x - a.x, vy = c.y - a.y, vi = ic - ia;
  const std::int64_t n_x = uy * vi - ui * vy, n_y = ui * vx - ux * vi, area2 = ux * vy - uy * vx;
  std::uint64_t sse = 0;
  *n_px = 0;
  const Box box = box_of(img, a, b, c);
  for (int y = box.y0; y <= box.y1; ++y) {
    for (int x = box.x0; x <= box.x1; ++x) {
      if (!owns_pixel(a, b, c, x, y, img.width, img.height)) continue;
      const std::int64_t r = n_x * (x - a.x) + n_y * (y - a.y) + area2 * (img.at(x, y) - ia);
      sse += static_cast<std::uint64_t>(r * r);
      ++*n_px;
    }
  }
  return sse;
}

PixelMoments moments_brute_force(const ImageU8& img, Vertex a, Vertex b, Vertex c, int ox, int oy) {
  PixelMoments m;
  const Box box = box_of(img, a, b, c);
  for (int y = box.y0; y <= box.y1; ++y) {
    for (int x = box.x0; x <= box.x1; ++x) {
      if (owns_pixel(a, b, c, x, y, img.width, img.height)) m.add_pixel(x - ox, y - oy, img.at(x, y));
    }
  }
  return m;
}

TEST(PixelMoments, PlaneSseEqualsBruteForceOnRandomTrianglesAndImages) {
  // Any triangle (not only the tritree's), any origin of the moments: the
  // expanded sum is the exact SSE, and the test decides as the model does.
  Rng rng(21);
  int splits = 0, keeps = 0, checked = 0;
  for (int it = 0; it < 4000; ++it) {
    const int w = rng.uniform(2, 70);
    const int h = rng.uniform(2, 70);
    const ImageU8 img = mixed_image(rng, w, h);
    Vertex v[3];
    for (Vertex& p : v) p = Vertex{rng.uniform(0, w - 1), rng.uniform(0, h - 1)};
    std::int64_t a2 = area2_of(v[0], v[1], v[2]);
    if (a2 == 0 || std::abs(a2) > 2 * kMaxAreaLimitPx2) continue;
    if (a2 < 0) std::swap(v[1], v[2]), a2 = -a2;
    const int ox = rng.uniform(0, w - 1), oy = rng.uniform(0, h - 1);
    const PixelMoments m = moments_brute_force(img, v[0], v[1], v[2], ox, oy);
    std::int64_t n_px = 0;
    const std::uint64_t expected = sse_brute_force(img, v[0], v[1], v[2], &n_px);
    ASSERT_EQ(m.n, n_px);
    PlaneCorner c[3];
    for (int i = 0; i < 3; ++i) c[i] = PlaneCorner{v[i].x - ox, v[i].y - oy, img.at(v[i].x, v[i].y)};
    ASSERT_EQ(plane_sse(m, c[0], c[1], c[2]), expected)
        << "triangle (" << v[0].x << "," << v[0].y << ") (" << v[1].x << "," << v[1].y << ") ("
        << v[2].x << "," << v[2].y << ") in " << w << "x" << h;
    // Any rotation of the corners is the same plane.
    ASSERT_EQ(plane_sse(m, c[1], c[2], c[0]), expected);
    const std::uint64_t mse_q8 = mse_threshold_q8(rng.uniform(kMinPsnrDeciDb, kMaxPsnrDeciDb));
    const bool fails = plane_fit_fails(expected, n_px, a2, mse_q8);
    const std::uint64_t ua2 = static_cast<std::uint64_t>(a2);
    EXPECT_EQ(fails, expected * 256 > mse_q8 * static_cast<std::uint64_t>(n_px) * ua2 * ua2);
    (fails ? splits : keeps) += 1;
    ++checked;
  }
  EXPECT_GT(checked, 2500);
  EXPECT_GT(splits, 500);  // both answers occur often
  EXPECT_GT(keeps, 500);
}

// plane_sse_of_fixed_shape for square side s and shape k of the corners
// table below ('\\' halves, '/' halves, side triangles top, right, bottom,
// left), u and v as the template arguments the plain tiles use.
template <int s>
std::uint64_t fixed_shape_sse_of_side(int k, const IntensityMoments& m, const ShapeMoments& g, int ax, int ay,
                                      int ia, int ib, int ic) {
  constexpr int h = s / 2;
  switch (k) {
    case 0: return plane_sse_of_fixed_shape<s, 0, s, s>(m, g, ax, ay, ia, ib, ic);
    case 1: return plane_sse_of_fixed_shape<s, s, 0, s>(m, g, ax, ay, ia, ib, ic);
    case 2: return plane_sse_of_fixed_shape<s, 0, 0, s>(m, g, ax, ay, ia, ib, ic);
    case 3: return plane_sse_of_fixed_shape<0, s, -s, s>(m, g, ax, ay, ia, ib, ic);
    case 4: return plane_sse_of_fixed_shape<s, 0, h, h>(m, g, ax, ay, ia, ib, ic);
    case 5: return plane_sse_of_fixed_shape<0, s, -h, h>(m, g, ax, ay, ia, ib, ic);
    case 6: return plane_sse_of_fixed_shape<-s, 0, -h, -h>(m, g, ax, ay, ia, ib, ic);
    default: return plane_sse_of_fixed_shape<0, -s, h, -h>(m, g, ax, ay, ia, ib, ic);
  }
}

std::uint64_t fixed_shape_sse(int s, int k, const IntensityMoments& m, const ShapeMoments& g, int ax, int ay,
                              int ia, int ib, int ic) {
  switch (s) {
    case 2: return fixed_shape_sse_of_side<2>(k, m, g, ax, ay, ia, ib, ic);
    case 4: return fixed_shape_sse_of_side<4>(k, m, g, ax, ay, ia, ib, ic);
    case 8: return fixed_shape_sse_of_side<8>(k, m, g, ax, ay, ia, ib, ic);
    case 16: return fixed_shape_sse_of_side<16>(k, m, g, ax, ay, ia, ib, ic);
    default: return fixed_shape_sse_of_side<32>(k, m, g, ax, ay, ia, ib, ic);
  }
}

TEST(PixelMoments, ShapeSseEqualsBruteForceAwayFromTheLastRowAndColumn) {
  // The plain tiles' test: geometric sums taken once per shape (at a far
  // placement, as Tritree::configure does), four intensity sums per triangle,
  // against the brute-force SSE at the triangle's own place in the image.
  Rng rng(47);
  int checked = 0, splits = 0;
  for (int it = 0; it < 3000; ++it) {
    const int s = 2 << rng.uniform(0, 4);  // square side 2 .. 32
    const int w = rng.uniform(s + 2, s + 40), h = rng.uniform(s + 2, s + 40);
    const ImageU8 img = mixed_image(rng, w, h);
    // A square whose corners stay off the last row and column; one of its two
    // halves ('\\' or '/') or one of its four side triangles.
    const int x0 = rng.uniform(0, w - 2 - s), y0 = rng.uniform(0, h - 2 - s), x1 = x0 + s, y1 = y0 + s;
    const int cx = x0 + s / 2, cy = y0 + s / 2;
    const Vertex corners[8][3] = {
        {{x0, y0}, {x1, y0}, {x1, y1}}, {{x0, y0}, {x1, y1}, {x0, y1}},  // '\\' halves
        {{x0, y0}, {x1, y0}, {x0, y1}}, {{x1, y0}, {x1, y1}, {x0, y1}},  // '/' halves
        {{x0, y0}, {x1, y0}, {cx, cy}}, {{x1, y0}, {x1, y1}, {cx, cy}},  // side triangles
        {{x1, y1}, {x0, y1}, {cx, cy}}, {{x0, y1}, {x0, y0}, {cx, cy}}};
    const int shape = rng.uniform(0, 7);
    const Vertex* v = corners[shape];
    ASSERT_GT(area2_of(v[0], v[1], v[2]), 0);
    ShapeMoments g;
    g.ux = v[1].x - v[0].x, g.uy = v[1].y - v[0].y, g.vx = v[2].x - v[0].x, g.vy = v[2].y - v[0].y;
    g.area2 = static_cast<std::int32_t>(area2_of(v[0], v[1], v[2]));
    const int far = 1000;
    const Vertex fa{far, far}, fb{far + g.ux, far + g.uy}, fc{far + g.vx, far + g.vy};
    for (int py = far - s; py <= far + s; ++py)
      for (int px = far - s; px <= far + s; ++px)
        if (owns_pixel(fa, fb, fc, px, py, 4 * far, 4 * far)) {
          const int dx = px - far, dy = py - far;
          g.n += 1, g.sx += dx, g.sy += dy, g.sxx += dx * dx, g.sxy += dx * dy, g.syy += dy * dy;
        }
    const int ox = rng.uniform(0, x0), oy = rng.uniform(0, y0);  // a tile origin at or before A
    IntensityMoments m;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        if (owns_pixel(v[0], v[1], v[2], x, y, w, h)) m.add_pixel(x - ox, y - oy, img.at(x, y));
    std::int64_t n_px = 0;
    const std::uint64_t expected = sse_brute_force(img, v[0], v[1], v[2], &n_px);
    ASSERT_EQ(g.n, n_px) << "the shape's pixels moved with the triangle";
    ASSERT_EQ(plane_sse_of_shape(m, g, v[0].x - ox, v[0].y - oy, img.at(v[0].x, v[0].y), img.at(v[1].x, v[1].y),
                                 img.at(v[2].x, v[2].y)),
              expected)
        << "square side " << s << " at " << x0 << "," << y0 << " in " << w << "x" << h;
    // The plain tiles' form with the shape's u and v as template arguments.
    ASSERT_EQ(fixed_shape_sse(s, shape, m, g, v[0].x - ox, v[0].y - oy, img.at(v[0].x, v[0].y),
                              img.at(v[1].x, v[1].y), img.at(v[2].x, v[2].y)),
              expected)
        << "fixed shape " << shape << ", side " << s;
    const std::uint64_t mse_q8 = mse_threshold_q8(400);
    splits += plane_fit_fails(expected, n_px, g.area2, mse_q8) ? 1 : 0;
    ++checked;
  }
  EXPECT_EQ(checked, 3000);
  EXPECT_GT(splits, 300);
  EXPECT_LT(splits, 2700);
}

// The six triangles of the square of side s at (x0, y0), corners in
// Tritree::corners() order: its side triangles (top, right, bottom, left),
// then its halves for `diagonal` (0: '\\' upper right, lower left; 1: '/'
// upper left, lower right).
std::array<std::array<Vertex, 3>, 6> square_triangles(int x0, int y0, int s, int diagonal) {
  const int x1 = x0 + s, y1 = y0 + s, cx = x0 + s / 2, cy = y0 + s / 2;
  std::array<std::array<Vertex, 3>, 6> t{};
  t[0] = {Vertex{x0, y0}, Vertex{x1, y0}, Vertex{cx, cy}};
  t[1] = {Vertex{x1, y0}, Vertex{x1, y1}, Vertex{cx, cy}};
  t[2] = {Vertex{x1, y1}, Vertex{x0, y1}, Vertex{cx, cy}};
  t[3] = {Vertex{x0, y1}, Vertex{x0, y0}, Vertex{cx, cy}};
  if (diagonal == 0) {
    t[4] = {Vertex{x0, y0}, Vertex{x1, y0}, Vertex{x1, y1}};
    t[5] = {Vertex{x0, y0}, Vertex{x1, y1}, Vertex{x0, y1}};
  } else {
    t[4] = {Vertex{x0, y0}, Vertex{x1, y0}, Vertex{x0, y1}};
    t[5] = {Vertex{x1, y0}, Vertex{x1, y1}, Vertex{x0, y1}};
  }
  return t;
}

TEST(Side4Tests, ScalarKernelEqualsBruteForce) {
  // The side-4 level's kernel (side4_shapes.hpp) against the fill rule and the
  // brute-force SSE: each pixel's owner, each triangle's SSE (pinned by a
  // limit just below it and one at it) and the halves' sums.
  Rng rng(53);
  int fails = 0, passes = 0;
  for (int it = 0; it < 2000; ++it) {
    const int w = rng.uniform(6, 40), h = rng.uniform(6, 40);
    const ImageU8 img = mixed_image(rng, w, h);
    // A square with corners at multiples of 4 (as in a tile), off the last row and column.
    const int x0 = 4 * rng.uniform(0, (w - 6) / 4), y0 = 4 * rng.uniform(0, (h - 6) / 4);
    const int diagonal = rng.uniform(0, 1);
    const auto tri = square_triangles(x0, y0, 4, diagonal);
    const auto corners_of = [&](int t) { return tri[static_cast<std::size_t>(t)].data(); };
    std::int32_t sse[6];
    std::int64_t pixels[6];
    std::int32_t sums[2][4] = {};
    for (int t = 0; t < 6; ++t) {
      const Vertex* v = corners_of(t);
      std::int64_t n_px = 0;
      const std::uint64_t e = sse_brute_force(img, v[0], v[1], v[2], &n_px);
      ASSERT_LT(e, std::uint64_t{1} << 27);
      sse[t] = static_cast<std::int32_t>(e);
      pixels[t] = n_px;
      for (int p = 0; p < 16; ++p) {
        const int dx = p & 3, dy = p >> 2;
        const bool owned = owns_pixel(v[0], v[1], v[2], x0 + dx, y0 + dy, w, h);
        const int side = side4::kSideOf[p];
        const bool listed = t < 4 ? side == t : side4::half_of(diagonal, side) == t - 4;
        ASSERT_EQ(owned, listed) << "pixel " << dx << "," << dy << " of triangle " << t << ", diagonal " << diagonal;
        if (t >= 4 && owned) {
          const std::int32_t i = img.at(x0 + dx, y0 + dy);
          std::int32_t* s = sums[t - 4];
          s[0] += i, s[1] += dx * i, s[2] += dy * i, s[3] += i * i;
        }
      }
    }
    const std::uint8_t* rows[5];
    for (int r = 0; r < 5; ++r) rows[r] = img.row(y0 + r) + x0;
    for (int below = 0; below < 2; ++below) {
      std::int32_t limit[side4::kLimits];
      for (int t = 0; t < 4; ++t) limit[side4::kLimitSide + t] = sse[t] - below;
      for (int p = 0; p < 2; ++p) {
        limit[side4::kLimitHalf + 2 * diagonal + p] = sse[4 + p] - below;
        limit[side4::kLimitHalf + 2 * (1 - diagonal) + p] = -1;  // the other diagonal's: would fail
      }
      std::uint32_t wants = 0xFFFFFFFFu;
      std::int32_t out[8 * 3];
      side4_tests_u8_scalar(rows, 1, diagonal == 0, limit, &wants, out, 3);
      for (int t = 0; t < 6; ++t) {
        const int bit = t < 4 ? t : side4::kWantsHalfBit + t - 4;
        ASSERT_EQ((wants >> bit) & 1u, below ? 1u : 0u) << "triangle " << t << " SSE " << sse[t];
      }
      ASSERT_EQ(wants >> 6, 0u);
      for (int c = 0; c < 8; ++c) ASSERT_EQ(out[3 * c], sums[c / 4][c % 4]) << "sum " << c;
    }
    for (int t = 0; t < 6; ++t)
      (plane_fit_fails(static_cast<std::uint64_t>(sse[t]), pixels[t], t < 4 ? 8 : 16, mse_threshold_q8(400)) ? fails
                                                                                                          : passes) += 1;
  }
  EXPECT_GT(fails, 1000);  // the images give both outcomes
  EXPECT_GT(passes, 1000);
}

TEST(Side8Tests, ScalarKernelEqualsBruteForce) {
  // The side-8 level's kernel (side8_shapes.hpp), fed by the side-4 kernel's
  // sums as the tritree feeds it, against the fill rule and the brute-force
  // SSE: each pixel's owner, each triangle's SSE (pinned by a limit just
  // below it and one at it) and the halves' sums.
  Rng rng(59);
  int fails = 0, passes = 0;
  for (int it = 0; it < 2000; ++it) {
    const int w = rng.uniform(10, 48), h = rng.uniform(10, 48);
    const ImageU8 img = mixed_image(rng, w, h);
    // A square with corners at multiples of 8 (as in a tile), off the last row and column.
    const int x0 = 8 * rng.uniform(0, (w - 10) / 8), y0 = 8 * rng.uniform(0, (h - 10) / 8);
    const int diagonal = rng.uniform(0, 1);
    const auto tri = square_triangles(x0, y0, 8, diagonal);
    const auto corners_of = [&](int t) { return tri[static_cast<std::size_t>(t)].data(); };
    std::int64_t sse[6], pixels[6];
    std::int64_t sums[2][4] = {};
    for (int t = 0; t < 6; ++t) {
      const Vertex* v = corners_of(t);
      std::int64_t n_px = 0;
      sse[t] = static_cast<std::int64_t>(sse_brute_force(img, v[0], v[1], v[2], &n_px));
      pixels[t] = n_px;
      const side8::Shape& g = t < 4 ? side8::kSide[t] : side8::kHalf[diagonal][t - 4];
      ASSERT_EQ(g.n, n_px) << "triangle " << t;
      for (int dy = 0; dy < 8; ++dy)
        for (int dx = 0; dx < 8; ++dx) {
          const bool owned = owns_pixel(v[0], v[1], v[2], x0 + dx, y0 + dy, w, h);
          const int side = side8::side_of(dx, dy);
          const bool listed = t < 4 ? side == t
                                    : (side == side8::kHalfSides[diagonal][t - 4][0] ||
                                       side == side8::kHalfSides[diagonal][t - 4][1]);
          ASSERT_EQ(owned, listed) << "pixel " << dx << "," << dy << " of triangle " << t << ", diagonal " << diagonal;
          if (t >= 4 && owned) {
            const std::int64_t i = img.at(x0 + dx, y0 + dy);
            std::int64_t* s = sums[t - 4];
            s[0] += i, s[1] += dx * i, s[2] += dy * i, s[3] += i * i;
          }
        }
    }
    // The side-4 level of the two rows of 4 x 4 squares (two squares each),
    // their diagonals alternating from the 8 x 8 square's quadrant (0, 0): '\\'.
    std::int32_t quad[2][8 * 2];
    for (int dy = 0; dy < 2; ++dy) {
      const std::uint8_t* rows4[5];
      for (int r = 0; r < 5; ++r) rows4[r] = img.row(y0 + 4 * dy + r) + x0;
      std::uint32_t wants4[2];
      const std::int32_t never[side4::kLimits] = {INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX,
                                                  INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX};
      side4_tests_u8_scalar(rows4, 2, dy == 0, never, wants4, quad[dy], 2);
    }
    const std::int32_t* quad_sums[2] = {quad[0], quad[1]};
    const std::uint8_t* rows[3] = {img.row(y0) + x0, img.row(y0 + 4) + x0, img.row(y0 + 8) + x0};
    for (int below = 0; below < 2; ++below) {
      std::int64_t limit[side8::kLimits];
      for (int t = 0; t < 4; ++t) limit[side8::kLimitSide + t] = sse[t] - below;
      for (int p = 0; p < 2; ++p) {
        limit[side8::kLimitHalf + 2 * diagonal + p] = sse[4 + p] - below;
        limit[side8::kLimitHalf + 2 * (1 - diagonal) + p] = -1;  // the other diagonal's: would fail
      }
      std::uint32_t wants = 0xFFFFFFFFu;
      std::int32_t out[8 * 3];
      side8_tests_s32_scalar(quad_sums, 2, rows, 1, diagonal == 0, limit, &wants, out, 3);
      for (int t = 0; t < 6; ++t) {
        const int bit = t < 4 ? t : side8::kWantsHalfBit + t - 4;
        ASSERT_EQ((wants >> bit) & 1u, below ? 1u : 0u) << "triangle " << t << " SSE " << sse[t];
      }
      ASSERT_EQ(wants >> 6, 0u);
      for (int c = 0; c < 8; ++c) ASSERT_EQ(out[3 * c], sums[c / 4][c % 4]) << "sum " << c;
    }
    for (int t = 0; t < 6; ++t)
      (plane_fit_fails(static_cast<std::uint64_t>(sse[t]), pixels[t], t < 4 ? 32 : 64, mse_threshold_q8(400)) ? fails
                                                                                                          : passes) += 1;
  }
  EXPECT_GT(fails, 1000);  // the images give both outcomes
  EXPECT_GT(passes, 1000);
}

TEST(PixelMoments, ChildrenAddUpToTheirParent) {
  // Bisecting a triangle at its hypotenuse's midpoint partitions its pixels
  // (the fill rule gives each pixel to one side), so moments add exactly.
  Rng rng(5);
  for (int it = 0; it < 2000; ++it) {
    const int w = rng.uniform(3, 40);
    const int h = rng.uniform(3, 40);
    const ImageU8 img = mixed_image(rng, w, h);
    const int s = 2 * rng.uniform(1, std::min(w - 1, h - 1) / 2);  // even legs
    const int x0 = rng.uniform(0, w - 1 - s), y0 = rng.uniform(0, h - 1 - s);
    // A right triangle with legs along the axes and its two children.
    const Vertex a{x0, y0}, b{x0 + s, y0 + s}, c{x0 + s, y0};  // hypotenuse a-b, apex c
    Vertex p[3] = {b, a, c};
    if (area2_of(p[0], p[1], p[2]) < 0) std::swap(p[0], p[1]);
    const Vertex m{(a.x + b.x) / 2, (a.y + b.y) / 2};
    Vertex c0[3] = {c, a, m}, c1[3] = {b, c, m};
    if (area2_of(c0[0], c0[1], c0[2]) < 0) std::swap(c0[0], c0[1]);
    if (area2_of(c1[0], c1[1], c1[2]) < 0) std::swap(c1[0], c1[1]);
    const PixelMoments parent = moments_brute_force(img, p[0], p[1], p[2], 0, 0);
    const PixelMoments sum = moments_brute_force(img, c0[0], c0[1], c0[2], 0, 0) +
                             moments_brute_force(img, c1[0], c1[1], c1[2], 0, 0);
    ASSERT_TRUE(parent == sum) << "square " << x0 << "," << y0 << " side " << s << " in " << w << "x" << h;
  }
}

// ------------------------------------------------------------ golden meshes

TEST(Tritree, Golden3x3ConstantHandDerived) {
  // W - 1 = H - 1 = 2: one tile of side 2 (A_max = 1), no stretch. Its halves
  // (area 2 > A_max) both want to split at the centre (1,1): 2 criterion
  // splits; the four side triangles have area 1 and cannot split.
  ImageU8 img(3, 3, 1, 77);
  TritreeParams params;
  params.max_area_px2 = 1;
  params.min_area_px2 = 1;  // the only one allowed with A_max = 1
  const Mesh m = build_mesh(img, params);
  const std::vector<Vertex> vertices = {{0, 0}, {2, 0}, {1, 1}, {0, 2}, {2, 2}};
  // In the hierarchy's order ('\\' tile): the upper right half (4, 0, 1)
  // gives (C, A, m) = (1, 4, 2), then (B, C, m) = (0, 1, 2); the lower left
  // (0, 4, 3) gives (3, 0, 2) -> (0, 2, 3), then (4, 3, 2) -> (2, 4, 3).
  const std::vector<Triangle> triangles = {{1, 4, 2}, {0, 1, 2}, {0, 2, 3}, {2, 4, 3}};
  EXPECT_EQ(m.vertices, vertices);
  EXPECT_EQ(m.triangles, triangles);
  EXPECT_EQ(m.row_start, (std::vector<std::int32_t>{0, 2, 3, 5}));
  EXPECT_EQ(m.criterion_splits, 2);
  EXPECT_EQ(m.forced_splits, 0);
  // With A_max = 2 the tile is 4 wide (virtual 2 x 2 inside it): the tile's
  // halves and side triangles cross the grid's border and split as virtual
  // triangles; the 2 x 2 square's halves (area 2) fit the constant plane.
  params.max_area_px2 = 2;
  const Mesh two = build_mesh(img, params);
  EXPECT_EQ(two.vertices, (std::vector<Vertex>{{0, 0}, {2, 0}, {0, 2}, {2, 2}}));
  EXPECT_EQ(two.triangles, (std::vector<Triangle>{{0, 1, 3}, {0, 3, 2}}));
  EXPECT_EQ(two.criterion_splits + two.forced_splits, 0);
  // A spike at the centre, A_max = 4 (the same 4-wide tile): with a minimum
  // area of 1 px^2 the half owning (1,1) fails the plane test and both halves
  // split at (1,1) (one by the criterion, one forced); with 2 px^2 a half of
  // area 2 does not want to split, so the mesh is the two halves again.
  ImageU8 spike(3, 3, 1, 0);
  spike.at(1, 1) = 255;
  params.max_area_px2 = 4;
  params.min_area_px2 = 1;
  const Mesh fine = build_mesh(spike, params);
  EXPECT_EQ(fine.vertices, vertices);
  EXPECT_EQ(fine.criterion_splits, 1);
  EXPECT_EQ(fine.forced_splits, 1);
  params.min_area_px2 = 2;
  const Mesh coarse = build_mesh(spike, params);
  EXPECT_EQ(coarse.vertices, (std::vector<Vertex>{{0, 0}, {2, 0}, {0, 2}, {2, 2}}));
  EXPECT_EQ(coarse.triangles, (std::vector<Triangle>{{0, 1, 3}, {0, 3, 2}}));
  EXPECT_EQ(coarse.criterion_splits + coarse.forced_splits, 0);
}

TEST(Tritree, Golden4x2StripAndStretched4x4) {
  // A side of 2 pixels: the diagonal's two triangles, never split.
  ImageU8 strip(4, 2, 1, 0);
  strip.at(1, 0) = 255;
  TritreeParams params;
  params.max_area_px2 = 1;
  params.min_area_px2 = 1;
  const Mesh s = build_mesh(strip, params);
  EXPECT_EQ(s.vertices, (std::vector<Vertex>{{0, 0}, {3, 0}, {0, 1}, {3, 1}}));
  EXPECT_EQ(s.triangles, (std::vector<Triangle>{{0, 1, 3}, {0, 3, 2}}));
  // 4 x 4: W - 1 = 3 is odd, so the virtual grid is 2 x 2 and its last column
  // and row sit on pixel 3. The halves of the stretched square have area
  // 4.5 > A_max = 1 and split at the virtual centre (1,1).
  const ImageU8 flat(4, 4, 1, 50);
  const Mesh f = build_mesh(flat, params);
  EXPECT_EQ(f.vertices, (std::vector<Vertex>{{0, 0}, {3, 0}, {1, 1}, {0, 3}, {3, 3}}));
  EXPECT_EQ(f.triangles, (std::vector<Triangle>{{1, 4, 2}, {0, 1, 2}, {0, 2, 3}, {2, 4, 3}}));
  EXPECT_EQ(f.criterion_splits, 2);
}

// ------------------------------------------------------------ invariants

// Checks every structural property of docs/model.md section 1 on `m`:
// raster vertices, triangles in tile order, coverage, one owner per pixel,
// conformity, area bounds, and that every leaf passes the criterion or
// cannot split.
void expect_valid_mesh(const ImageU8& gray, const TritreeParams& params, const Mesh& m,
                       bool check_criterion = true) {
  const int w = gray.width, h = gray.height;
  ASSERT_EQ(m.width, w);
  ASSERT_EQ(m.height, h);
  ASSERT_EQ(m.row_start.size(), static_cast<std::size_t>(h) + 1);
  ASSERT_EQ(m.row_start.front(), 0);
  ASSERT_EQ(m.row_start.back(), static_cast<std::int32_t>(m.vertices.size()));
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    const Vertex& v = m.vertices[i];
    ASSERT_TRUE(v.x >= 0 && v.x < w && v.y >= 0 && v.y < h);
    ASSERT_GE(static_cast<std::int32_t>(i), m.row_start[v.y]);
    ASSERT_LT(static_cast<std::int32_t>(i), m.row_start[v.y + 1]);
    if (i > 0) {
      const Vertex& p = m.vertices[i - 1];
      ASSERT_TRUE(p.y < v.y || (p.y == v.y && p.x < v.x));
    }
  }
  std::vector<std::int32_t> grid(static_cast<std::size_t>(w) * h, -1);
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    grid[static_cast<std::size_t>(m.vertices[i].y) * w + m.vertices[i].x] = static_cast<std::int32_t>(i);
  }
  std::vector<char> used(m.vertices.size(), 0);

  // Triangles rotated to their smallest id, in the hierarchy's order (tiles
  // in raster order: a triangle's tile holds its smallest virtual corner
  // coordinates), positive orientation, areas tile the rectangle, area >=
  // 1 px^2 (the two triangles of a strip image excepted).
  const RtinLayout layout(w, h, params.max_area_px2);
  const auto tile_of = [&](const Triangle& t) {
    int vx = INT_MAX, vy = INT_MAX;
    for (int c = 0; c < 3; ++c) {
      const Vertex& v = m.vertices[static_cast<std::size_t>(t[c])];
      vx = std::min(vx, layout.stretch_x && v.x == w - 1 ? layout.vw : v.x);
      vy = std::min(vy, layout.stretch_y && v.y == h - 1 ? layout.vh : v.y);
    }
    return (vy / layout.tile) * layout.tiles_x + vx / layout.tile;
  };
  std::int64_t area_sum = 0;
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    const Triangle& t = m.triangles[i];
    ASSERT_TRUE(t[0] < t[1] && t[0] < t[2]);
    if (i > 0 && !layout.strip()) {
      ASSERT_LE(tile_of(m.triangles[i - 1]), tile_of(t)) << "triangle " << i << " out of tile order";
    }
    const std::int64_t a2 = area2_of(m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]);
    ASSERT_GT(a2, 0);
    if (!layout.strip()) {
      ASSERT_GE(a2, 2);
    }
    area_sum += a2;
    for (int c = 0; c < 3; ++c) used[static_cast<std::size_t>(t[c])] = 1;
  }
  EXPECT_EQ(area_sum, 2 * std::int64_t{w - 1} * (h - 1));
  for (std::size_t i = 0; i < used.size(); ++i) ASSERT_TRUE(used[i]) << "vertex " << i << " unused";

  // Every pixel owned by exactly one triangle (checked pixel by pixel).
  std::vector<int> owners(static_cast<std::size_t>(w) * h, 0);
  for (const Triangle& t : m.triangles) {
    const Vertex a = m.vertices[t[0]], b = m.vertices[t[1]], c = m.vertices[t[2]];
    for (int y = std::min({a.y, b.y, c.y}); y <= std::max({a.y, b.y, c.y}); ++y) {
      for (int x = std::min({a.x, b.x, c.x}); x <= std::max({a.x, b.x, c.x}); ++x) {
        if (owns_pixel(a, b, c, x, y, w, h)) ++owners[static_cast<std::size_t>(y) * w + x];
      }
    }
  }
  for (std::size_t p = 0; p < owners.size(); ++p) ASSERT_EQ(owners[p], 1) << "pixel " << p;

  // Conforming: no vertex on an edge (other than its endpoints) or inside a
  // triangle. Lattice points of edge AB are A + k (AB / g), g = gcd.
  for (const Triangle& t : m.triangles) {
    for (int e = 0; e < 3; ++e) {
      const Vertex a = m.vertices[t[e]], b = m.vertices[t[(e + 1) % 3]];
      const int dx = b.x - a.x, dy = b.y - a.y;
      const int g = std::gcd(std::abs(dx), std::abs(dy));
      for (int k = 1; k < g; ++k) {
        const int x = a.x + k * dx / g, y = a.y + k * dy / g;
        ASSERT_EQ(grid[static_cast<std::size_t>(y) * w + x], -1)
            << "hanging vertex (" << x << "," << y << ") on edge (" << a.x << "," << a.y
            << ")-(" << b.x << "," << b.y << ")";
      }
    }
    const Vertex a = m.vertices[t[0]], b = m.vertices[t[1]], c = m.vertices[t[2]];
    for (int y = std::min({a.y, b.y, c.y}); y <= std::max({a.y, b.y, c.y}); ++y) {
      for (int x = std::min({a.x, b.x, c.x}); x <= std::max({a.x, b.x, c.x}); ++x) {
        const Vertex p{x, y};
        if (area2_of(a, b, p) > 0 && area2_of(b, c, p) > 0 && area2_of(c, a, p) > 0) {
          ASSERT_EQ(grid[static_cast<std::size_t>(y) * w + x], -1) << "vertex inside a triangle";
        }
      }
    }
  }
  if (!check_criterion || layout.strip()) return;

  // Every leaf passes the criterion (area, then PSNR by brute force) unless it
  // may not want to split: its virtual area (undo the stretch) is below twice
  // the minimum area. A leaf below the minimum area itself comes from a split
  // forced by a crossing triangle (docs/model.md): only with a minimum area
  // above 2 px^2 (smaller triangles never cross) and partial tiles.
  const std::uint64_t mse_q8 = mse_threshold_q8(params.psnr_deci_db);
  const auto virtual_of = [&](const Vertex& v) {
    return Vertex{layout.stretch_x && v.x == w - 1 ? layout.vw : v.x,
                  layout.stretch_y && v.y == h - 1 ? layout.vh : v.y};
  };
  for (const Triangle& t : m.triangles) {
    const Vertex a = m.vertices[t[0]], b = m.vertices[t[1]], c = m.vertices[t[2]];
    const Vertex va = virtual_of(a), vb = virtual_of(b), vc = virtual_of(c);
    const std::int64_t virtual_a2 = area2_of(va, vb, vc);
    if (virtual_a2 < 2 * std::int64_t{params.min_area_px2}) {
      ASSERT_GT(params.min_area_px2, 2) << "leaf below the minimum area";
      ASSERT_TRUE(layout.tiles_x * layout.tile > layout.vw || layout.tiles_y * layout.tile > layout.vh)
          << "leaf below the minimum area without partial tiles";
    }
    if (virtual_a2 < 4 * std::int64_t{params.min_area_px2}) continue;
    const std::int64_t a2 = area2_of(a, b, c);
    ASSERT_LE(a2, 2 * params.max_area_px2) << "leaf larger than A_max";
    std::int64_t n_px = 0;
    const std::uint64_t sse = sse_brute_force(gray, a, b, c, &n_px);
    ASSERT_FALSE(plane_fit_fails(sse, n_px, a2, mse_q8))
        << "leaf (" << a.x << "," << a.y << ") (" << b.x << "," << b.y << ") (" << c.x << ","
        << c.y << ") fails the PSNR test";
  }
}

TEST(Tritree, InvariantsOnRandomImages) {
  Rng rng(2024);
  for (int it = 0; it < 300; ++it) {
    const int w = rng.uniform(2, 48);
    const int h = rng.uniform(2, 48);
    const ImageU8 img = mixed_image(rng, w, h);
    TritreeParams params;
    params.psnr_deci_db = rng.uniform(kMinPsnrDeciDb, kMaxPsnrDeciDb);
    params.max_area_px2 = rng.uniform(1, 64);
    params.min_area_px2 = rng.uniform(1, largest_min_area_px2(params.max_area_px2));
    const Mesh m = build_mesh(img, params);
    SCOPED_TRACE(::testing::Message() << "image " << it << " " << w << "x" << h << " A_min " << params.min_area_px2);
    expect_valid_mesh(img, params, m);
    if (HasFatalFailure()) return;
  }
}

TEST(Tritree, InvariantsOnSpecialSizes) {
  // 2 x 2, 3 x N, primes, thin and 4096 wide.
  const std::pair<int, int> sizes[] = {{2, 2},  {2, 3},  {3, 2},   {3, 3},  {3, 17},  {17, 3},
                                       {3, 64}, {5, 7},  {7, 5},   {13, 31}, {31, 13}, {37, 41},
                                       {97, 89}, {127, 2}, {4096, 3}, {4096, 5}, {4095, 4}, {2, 4096}};
  Rng rng(77);
  for (const auto& size : sizes) {
    for (int area : {1, 7, 100}) {
      for (int min_area : {1, largest_min_area_px2(area)}) {
        const ImageU8 img = mixed_image(rng, size.first, size.second);
        TritreeParams params;
        params.max_area_px2 = area;
        params.min_area_px2 = min_area;
        const Mesh m = build_mesh(img, params);
        SCOPED_TRACE(::testing::Message() << size.first << "x" << size.second << " A_max " << area << " A_min "
                                          << min_area);
        expect_valid_mesh(img, params, m, /*check_criterion=*/size.first * size.second < 20000);
        if (HasFatalFailure()) return;
      }
    }
  }
}

TEST(Tritree, InvariantsOnMiddlebury) {
  TRISTEREO_REQUIRE_MIDDLEBURY();
  for (const std::string& name : test::middlebury_names()) {
    const ImageU8 gray = to_gray(test::load_middlebury(name).left);
    for (const TritreeParams& params : {TritreeParams{}, paper_params().tritree}) {  // 44 dB, 2 px^2; 40 dB, 1 px^2
      const Mesh m = build_mesh(gray, params);
      SCOPED_TRACE(name + " A_min " + std::to_string(params.min_area_px2));
      expect_valid_mesh(gray, params, m);
      EXPECT_GT(m.vertices.size(), 1000u);  // a textured scene is refined well below A_max
    }
  }
}

TEST(Tritree, DeterministicAndReusable) {
  Rng rng(7);
  const ImageU8 a = mixed_image(rng, 61, 37);
  const ImageU8 b = mixed_image(rng, 20, 50);
  TritreeParams params;
  params.max_area_px2 = 20;
  Tritree tree;
  tree.configure(64, 64, params);
  Mesh m1, m2, m3;
  tree.reserve(m1);
  tree.build(cview(a), m1);
  tree.build(cview(b), m2);  // a different size in between
  tree.build(cview(a), m3);
  EXPECT_EQ(m1, m3);
  EXPECT_EQ(m1, build_mesh(a, params));
  EXPECT_EQ(m2, build_mesh(b, params));
  EXPECT_FALSE(m1 == m2);
}

TEST(Tritree, BuildDoesNotAllocate) {
  Rng rng(12);
  const ImageU8 small = mixed_image(rng, 30, 20);
  const ImageU8 large = mixed_image(rng, 90, 70);
  TritreeParams params;
  params.max_area_px2 = 4;  // deep refinement
  params.min_area_px2 = 1;
  Tritree tree;
  tree.configure(90, 70, params);
  Mesh mesh;
  tree.reserve(mesh);
  tree.build(cview(small), mesh);  // warm-up
  test::start_counting_allocations();
  tree.build(cview(large), mesh);
  tree.build(cview(small), mesh);
  EXPECT_EQ(test::stop_counting_allocations(), 0);
  EXPECT_GT(mesh.vertices.size(), 50u);
}

TEST(Tritree, IdenticalForAnyThreadCount) {
  // Pass 1 runs rows of tiles on the pool (even rows, then odd ones): any
  // pool gives the serial mesh, on partial tiles and stretched borders too.
  Rng rng(31);
  for (const auto& size : {std::pair<int, int>{150, 101}, std::pair<int, int>{451, 376}}) {
    const ImageU8 img = mixed_image(rng, size.first, size.second);
    for (const auto& [area, min_area] : {std::pair<int, int>{4, 1}, {100, 1}, {100, 2}, {100, 8}}) {
      TritreeParams params;
      params.max_area_px2 = area;
      params.min_area_px2 = min_area;
      const Mesh serial = build_mesh(img, params);
      for (int workers : {1, 2, 3}) {
        ThreadPool pool;
        pool.start(workers, {}, /*pin=*/false);
        Tritree tree;
        tree.configure(img.width, img.height, params);
        Mesh mesh;
        tree.reserve(mesh);
        tree.build(cview(img), mesh, &pool);
        EXPECT_EQ(mesh, serial) << workers << " workers, " << size.first << "x" << size.second << " A_max " << area
                                << " A_min " << min_area;
      }
    }
  }
}

TEST(Tritree, ReusedTreeEqualsFreshOnEveryFrame) {
  // A tree reused across frames replays the general tiles' span records it
  // made on earlier ones (Tritree::SpanCache): new contents at the same size,
  // then sizes whose last column and row are or are not moved, and back.
  Rng rng(41);
  const std::pair<int, int> sizes[] = {{451, 376}, {451, 376}, {450, 375}, {449, 377}, {130, 67}, {451, 376}};
  for (const auto& [area, min_area] : {std::pair<int, int>{100, 2}, {100, 1}, {30, 4}, {1024, 2}}) {
    TritreeParams params;
    params.max_area_px2 = area;
    params.min_area_px2 = min_area;
    ThreadPool pool;
    pool.start(2, {}, /*pin=*/false);
    Tritree reused, reused_pool;
    reused.configure(451, 377, params);
    reused_pool.configure(451, 377, params);
    Mesh m, mp;
    reused.reserve(m);
    reused_pool.reserve(mp);
    for (const auto& [w, h] : sizes) {
      const ImageU8 img = mixed_image(rng, w, h);
      const Mesh fresh = build_mesh(img, params);
      reused.build(cview(img), m);
      reused_pool.build(cview(img), mp, &pool);
      EXPECT_EQ(m, fresh) << w << "x" << h << " A_max " << area << " A_min " << min_area;
      EXPECT_EQ(mp, fresh) << w << "x" << h << " A_max " << area << " A_min " << min_area << ", 2 workers";
    }
  }
}

TEST(Tritree, StrideMatchesPackedBuild) {
  Rng rng(8);
  const ImageU8 img = mixed_image(rng, 33, 21);
  TritreeParams params;
  params.max_area_px2 = 10;
  // Same pixels, rows padded to 40 bytes.
  std::vector<std::uint8_t> padded(40 * 21, 0xAB);
  for (int y = 0; y < 21; ++y) std::copy(img.row(y), img.row(y) + 33, padded.data() + 40 * y);
  const ImageView<const std::uint8_t> view{padded.data(), 33, 21, 1, 40};
  Tritree tree;
  tree.configure(33, 21, params);
  Mesh strided;
  tree.build(view, strided);
  EXPECT_EQ(strided, build_mesh(img, params));
  EXPECT_GT(strided.vertices.size(), 20u);
}

TEST(Tritree, CountsCriterionAndForcedSplits) {
  // Both kinds occur; a split replaces one triangle by two, and the inside
  // tiles' halves are the starting triangles.
  Rng rng(9);
  const ImageU8 img = mixed_image(rng, 65, 33);  // W-1 = 64, H-1 = 32: whole tiles
  TritreeParams params;
  params.max_area_px2 = 8;
  const Mesh m = build_mesh(img, params);
  const RtinLayout layout(65, 33, params.max_area_px2);
  const std::int64_t roots = 2 * layout.tiles_x * layout.tiles_y;
  EXPECT_EQ(static_cast<std::int64_t>(m.triangles.size()), roots + m.criterion_splits + m.forced_splits);
  EXPECT_GT(m.forced_splits, 0);
  EXPECT_GT(m.criterion_splits, m.forced_splits);
}

TEST(Tritree, ReportsItsMemory) {
  Tritree tree;
  EXPECT_EQ(tree.working_memory_bytes(), 0u);
  tree.configure(640, 480, TritreeParams{});
  const double per_pixel = static_cast<double>(tree.working_memory_bytes()) / (640.0 * 480.0);
  // The need byte, each pass-3 worker's S + 2 rows of vertex ids and the
  // tile scratch; no W x H grid of ids (4 B more). The leaves go straight
  // into the mesh, whose capacity is the caller's (reserve()).
  const double ids = Tritree::kMaxTileWorkers * (tree.tile_side() + 2) * 640.0 * 4.0 / (640.0 * 480.0);
  EXPECT_GT(per_pixel, 1.0 + ids);
  EXPECT_LT(per_pixel, 1.0 + ids + 3.0);
}

// ------------------------------------------------------------ bad input

TEST(Tritree, RejectsBadConfiguration) {
  Tritree tree;
  TritreeParams ok;
  EXPECT_THROW(tree.configure(1, 10, ok), Error);
  EXPECT_THROW(tree.configure(10, kMaxImageSide + 1, ok), Error);
  TritreeParams bad = ok;
  bad.max_area_px2 = 0;
  EXPECT_THROW(tree.configure(10, 10, bad), Error);
  bad.max_area_px2 = kMaxAreaLimitPx2 + 1;
  EXPECT_THROW(tree.configure(10, 10, bad), Error);
  bad = ok;
  bad.min_area_px2 = 0;
  EXPECT_THROW(tree.configure(10, 10, bad), Error);
  bad.min_area_px2 = largest_min_area_px2(bad.max_area_px2) + 1;
  EXPECT_THROW(tree.configure(10, 10, bad), Error);
  bad = ok;
  bad.psnr_deci_db = kMinPsnrDeciDb - 1;
  EXPECT_THROW(tree.configure(10, 10, bad), Error);
  bad.psnr_deci_db = kMaxPsnrDeciDb + 1;
  try {
    tree.configure(10, 10, bad);
    FAIL() << "no throw";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(e.what()).find("701"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(tree.configured());
}

TEST(Tritree, RejectsBadImagesWithoutTouchingTheMesh) {
  Tritree tree;
  const ImageU8 img(8, 8, 1, 3);
  Mesh mesh;
  EXPECT_THROW(tree.build(cview(img), mesh), Error);  // not configured
  tree.configure(16, 16, TritreeParams{});
  Mesh before;
  before.width = 123;
  before.vertices = {{1, 2}};
  mesh = before;
  ImageView<const std::uint8_t> v = cview(img);
  auto expect_rejected = [&](ImageView<const std::uint8_t> bad) {
    EXPECT_THROW(tree.build(bad, mesh), Error);
    EXPECT_EQ(mesh, before);
  };
  ImageView<const std::uint8_t> bad = v;
  bad.data = nullptr;
  expect_rejected(bad);
  bad = v;
  bad.width = 1;
  expect_rejected(bad);
  bad = v;
  bad.height = 1;
  expect_rejected(bad);
  const ImageU8 big(17, 8, 1, 0);
  expect_rejected(cview(big));
  bad = v;
  bad.channels = 3;
  expect_rejected(bad);
  bad = v;
  bad.stride_bytes = 7;
  expect_rejected(bad);
  tree.build(v, mesh);  // still usable afterwards
  EXPECT_EQ(mesh, build_mesh(img, TritreeParams{}));
}

}  // namespace
}  // namespace tristereo

