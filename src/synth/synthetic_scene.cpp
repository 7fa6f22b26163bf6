// Synthetic stereo scenes: see include/tristereo/synth.hpp for the model.
//
// Fixed-point conventions used throughout this file:
//  - disparities and x positions are Q16 (value / 65536 = pixels);
//  - a surface's disparity is the plane d(x, y) = a + b x + c y (a in Q16,
//    b and c in Q16 per pixel) in left-image coordinates;
//  - texture samples are Q4 gray levels (0 .. 4080).
#include "tristereo/synth.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "tristereo/fixed_point.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

namespace {

constexpr int kQ = 16;
constexpr std::int64_t kOne = std::int64_t{1} << kQ;

// splitmix64: tiny, fully specified, identical everywhere (unlike the
// std::uniform_*_distribution adaptors, whose output is library-specific).
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // Uniform in [lo, hi] (hi >= lo); the modulo bias is irrelevant here.
  std::int64_t range(std::int64_t lo, std::int64_t hi) {
    return lo + static_cast<std::int64_t>(next() % static_cast<std::uint64_t>(hi - lo + 1));
  }

 private:
  std::uint64_t state_;
};

// A texture lattice covering [x0, x0 + w) x [y0, y0 + h) in surface coordinates.
struct Texture {
  int x0 = 0, y0 = 0, w = 0, h = 0;
  std::vector<std::int32_t> q4;  // w * h Q4 gray levels

  // Linear interpolation along x at u_q16 (Q16), row v; coordinates outside
  // the lattice are clamped to its border.
  std::int32_t sample(std::int64_t u_q16, std::int64_t v) const {
    const std::int64_t whole = floor_div(u_q16, kOne);
    const std::int64_t f = u_q16 - whole * kOne;  // 0 .. kOne - 1
    std::int64_t ui = whole - x0;
    std::int64_t vi = std::clamp<std::int64_t>(v - y0, 0, h - 1);
    ui = std::clamp<std::int64_t>(ui, 0, w - 1);
    const std::int64_t ui1 = std::min<std::int64_t>(ui + 1, w - 1);
    const std::int32_t* row = q4.data() + vi * w;
    // f == 0 returns row[ui] exactly: integer positions never interpolate.
    return static_cast<std::int32_t>((row[ui] * (kOne - f) + row[ui1] * f + kOne / 2) >> kQ);
  }
};

// Smoothed noise at two scales plus a linear gradient around a base level.
Texture make_texture(int x0, int y0, int w, int h, SplitMix64& rng) {
  Texture t;
  t.x0 = x0;
  t.y0 = y0;
  t.w = w;
  t.h = h;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  const std::int64_t base = rng.range(70, 185) * 16;
  const std::int64_t grad_x = rng.range(-40, 40) * 16;  // total change across the lattice
  const std::int64_t grad_y = rng.range(-40, 40) * 16;

  // Fine noise: uniform +-96 levels, 3x3 box filtered.
  std::vector<std::int32_t> fine(n);
  for (auto& v : fine) v = static_cast<std::int32_t>(rng.range(-96, 96) * 16);
  // Coarse noise: a +-40-level grid every 8 pixels, interpolated bilinearly.
  constexpr int kCell = 8;
  const int cw = w / kCell + 2, ch = h / kCell + 2;
  std::vector<std::int32_t> coarse(static_cast<std::size_t>(cw) * ch);
  for (auto& v : coarse) v = static_cast<std::int32_t>(rng.range(-40, 40) * 16);

  t.q4.resize(n);
  for (int y = 0; y < h; ++y) {
    const int cy = y / kCell, fy = y % kCell;
    for (int x = 0; x < w; ++x) {
      std::int64_t box = 0;
      for (int dy = -1; dy <= 1; ++dy) {
        const int yy = std::clamp(y + dy, 0, h - 1);
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = std::clamp(x + dx, 0, w - 1);
          box += fine[static_cast<std::size_t>(yy) * w + xx];
        }
      }
      const int cx = x / kCell, fx = x % kCell;
      const std::int64_t c00 = coarse[cy * cw + cx], c10 = coarse[cy * cw + cx + 1];
      const std::int64_t c01 = coarse[(cy + 1) * cw + cx], c11 = coarse[(cy + 1) * cw + cx + 1];
      const std::int64_t top = c00 * (kCell - fx) + c10 * fx;
      const std::int64_t bot = c01 * (kCell - fx) + c11 * fx;
      const std::int64_t coarse_v = floor_div(top * (kCell - fy) + bot * fy, kCell * kCell);
      const std::int64_t gradient = floor_div(grad_x * x, std::max(1, w - 1)) +
                                    floor_div(grad_y * y, std::max(1, h - 1)) -
                                    (grad_x + grad_y) / 2;
      const std::int64_t v = base + floor_div(box, 9) + coarse_v + gradient;
      t.q4[static_cast<std::size_t>(y) * w + x] =
          static_cast<std::int32_t>(std::clamp<std::int64_t>(v, 0, 255 * 16));
    }
  }
  return t;
}

enum class Shape { kEverywhere, kRect, kDisc };

struct Surface {
  std::int64_t a = 0, b = 0, c = 0;  // disparity plane, Q16
  Shape shape = Shape::kEverywhere;
  std::int64_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // rect, inclusive pixel bounds
  std::int64_t cx = 0, cy = 0, r = 0;           // disc
  std::int64_t shift_x = 0, shift_y = 0;        // texture moves with the object
  Texture tex;

  bool contains(std::int64_t x_q16, std::int64_t y) const {
    switch (shape) {
      case Shape::kEverywhere:
        return true;
      case Shape::kRect:
        return y >= y0 && y <= y1 && x_q16 >= x0 * kOne && x_q16 <= x1 * kOne;
      case Shape::kDisc: {
        const std::int64_t dx = x_q16 - cx * kOne, dy = (y - cy) * kOne;
        return dx * dx + dy * dy <= (r * kOne) * (r * kOne);
      }
    }
    return false;
  }
  std::int64_t disp_q16(std::int64_t x_q16, std::int64_t y) const {
    return a + floor_div(b * x_q16, kOne) + c * y;
  }
  std::int32_t texture_q4(std::int64_t x_q16, std::int64_t y) const {
    return tex.sample(x_q16 - shift_x * kOne, y - shift_y);
  }
};

std::uint8_t to_u8(std::int32_t q4) {
  return static_cast<std::uint8_t>(std::clamp((q4 + 8) >> 4, 0, 255));
}

// Renders both views and the ground truth from the surface list.
SyntheticScene render(const std::vector<Surface>& surfaces, int w, int h) {
  SyntheticScene s;
  s.left = ImageU8(w, h, 1);
  s.right = ImageU8(w, h, 1);
  s.disp_left = Image<float>(w, h, 1);
  s.nonocc_mask = ImageU8(w, h, 1);
  const int ns = static_cast<int>(surfaces.size());
  std::vector<int> left_owner(static_cast<std::size_t>(w)), right_owner(static_cast<std::size_t>(w));
  std::vector<std::int64_t> left_d(static_cast<std::size_t>(w));
  for (int y = 0; y < h; ++y) {
    // Left view: the nearest surface covering (x, y); later surfaces win ties.
    for (int x = 0; x < w; ++x) {
      int best = -1;
      std::int64_t best_d = std::numeric_limits<std::int64_t>::min();
      const std::int64_t xq = static_cast<std::int64_t>(x) << kQ;
      for (int i = 0; i < ns; ++i) {
        if (!surfaces[i].contains(xq, y)) continue;
        const std::int64_t d = surfaces[i].disp_q16(xq, y);
        if (d >= best_d) {
          best = i;
          best_d = d;
        }
      }
      left_owner[x] = best;
      left_d[x] = best_d;
      s.left.at(x, y) = to_u8(surfaces[best].texture_q4(xq, y));
      // best_d < 2^24: exact in float.
      s.disp_left.at(x, y) = static_cast<float>(best_d) / static_cast<float>(kOne);
    }
    // Right view: right pixel xr sees surface point xl with xl - d(xl) = xr,
    // i.e. xl = (xr + a + c y) / (1 - b); the nearest such point wins.
    for (int xr = 0; xr < w; ++xr) {
      int best = -1;
      std::int64_t best_d = std::numeric_limits<std::int64_t>::min(), best_xl = 0;
      for (int i = 0; i < ns; ++i) {
        const Surface& sf = surfaces[i];
        const std::int64_t num = (static_cast<std::int64_t>(xr) << kQ) + sf.a + sf.c * y;
        const std::int64_t xl = floor_div(num * kOne, kOne - sf.b);
        if (!sf.contains(xl, y)) continue;
        const std::int64_t d = sf.disp_q16(xl, y);
        if (d >= best_d) {
          best = i;
          best_d = d;
          best_xl = xl;
        }
      }
      right_owner[xr] = best;
      s.right.at(xr, y) = best < 0 ? 0 : to_u8(surfaces[best].texture_q4(best_xl, y));
    }
    // Visible in both views: the point lands inside the right image and the
    // right pixels around it show the same surface.
    for (int x = 0; x < w; ++x) {
      const std::int64_t xr_q16 = (static_cast<std::int64_t>(x) << kQ) - left_d[x];
      bool visible = xr_q16 >= 0;
      if (visible) {
        const std::int64_t xr0 = xr_q16 >> kQ;
        const std::int64_t xr1 = xr0 + ((xr_q16 & (kOne - 1)) ? 1 : 0);
        visible = xr1 < w && right_owner[xr0] == left_owner[x] && right_owner[xr1] == left_owner[x];
      }
      s.nonocc_mask.at(x, y) = visible ? 255 : 0;
    }
  }
  return s;
}

std::uint64_t stream_seed(std::uint32_t seed, int index) {
  // Distinct, well-mixed streams per surface so adding a surface later does
  // not change the others.
  SplitMix64 m((static_cast<std::uint64_t>(seed) << 20) ^ static_cast<std::uint64_t>(index + 1));
  return m.next();
}

[[noreturn]] void bad_param(const std::string& what) {
  throw Error(ErrorCode::kInvalidArgument, what);
}

}  // namespace

SyntheticScene make_planar_scene(int w, int h, int disp, std::uint32_t seed) {
  if (w < 2 || w > 4096 || h < 2 || h > 4096) {
    bad_param("make_planar_scene: size " + std::to_string(w) + " x " + std::to_string(h) +
              " is outside 2..4096");
  }
  if (disp < 0 || disp >= w) {
    bad_param("make_planar_scene: disparity " + std::to_string(disp) + " is outside 0.." +
              std::to_string(w - 1));
  }
  SplitMix64 rng(stream_seed(seed, 0));
  Surface plane;
  plane.a = static_cast<std::int64_t>(disp) << kQ;
  plane.tex = make_texture(0, 0, w + disp + 1, h, rng);
  return render({plane}, w, h);
}

SyntheticScene make_synthetic_scene(const SynthParams& p) {
  if (p.width < 16 || p.width > 4096 || p.height < 16 || p.height > 4096) {
    bad_param("make_synthetic_scene: size " + std::to_string(p.width) + " x " +
              std::to_string(p.height) + " is outside 16..4096");
  }
  if (p.num_disp < 8 || p.num_disp > 256) {
    bad_param("make_synthetic_scene: num_disp " + std::to_string(p.num_disp) +
              " is outside 8..256");
  }
  if (p.frame < 0 || p.frame > 100000) {
    bad_param("make_synthetic_scene: frame " + std::to_string(p.frame) + " is outside 0..100000");
  }
  const int w = p.width, h = p.height, nd = p.num_disp;
  std::vector<Surface> surfaces;

  // Background: slanted plane with disparities in [1, bg_hi].
  const std::int64_t bg_hi = std::max(2, nd / 4);
  {
    SplitMix64 rng(stream_seed(p.seed, 0));
    Surface bg;
    const std::int64_t range = (bg_hi - 1) * kOne;
    const std::int64_t rx = range * rng.range(30, 70) / 100;
    const std::int64_t ry = range - rx;
    // |slope| <= 1/4 px per px keeps 1 - b far from 0 and the surface sane.
    bg.b = std::min(rx / (w - 1), kOne / 4) * (rng.range(0, 1) ? 1 : -1);
    bg.c = std::min(ry / (h - 1), kOne / 4) * (rng.range(0, 1) ? 1 : -1);
    bg.a = kOne - std::min<std::int64_t>(0, bg.b * (w - 1)) - std::min<std::int64_t>(0, bg.c * (h - 1));
    // The right view reaches left coordinates up to w - 1 + bg_hi.
    bg.tex = make_texture(0, 0, w + static_cast<int>(bg_hi) + 2, h, rng);
    surfaces.push_back(std::move(bg));
  }

  // Fronto-parallel objects at integer disparities in [bg_hi + 1, nd - 1].
  constexpr int kObjects = 5;
  const int min_side = std::min(w, h);
  for (int k = 0; k < kObjects; ++k) {
    SplitMix64 rng(stream_seed(p.seed, 1 + k));
    Surface o;
    o.shape = (k % 2 == 0) ? Shape::kRect : Shape::kDisc;
    o.a = rng.range(bg_hi + 1, nd - 1) * kOne;
    const std::int64_t vx = rng.range(-3, 3), vy = rng.range(-2, 2);
    o.shift_x = vx * p.frame;
    o.shift_y = vy * p.frame;
    int bx0, by0, bw, bh;  // bounding box at frame 0
    if (o.shape == Shape::kRect) {
      bw = static_cast<int>(rng.range(w / 8, w / 3));
      bh = static_cast<int>(rng.range(h / 8, h / 3));
      bx0 = static_cast<int>(rng.range(0, w - bw));
      by0 = static_cast<int>(rng.range(0, h - bh));
      o.x0 = bx0 + o.shift_x;
      o.y0 = by0 + o.shift_y;
      o.x1 = o.x0 + bw - 1;
      o.y1 = o.y0 + bh - 1;
    } else {
      const int r = static_cast<int>(rng.range(std::max(2, min_side / 12), std::max(3, min_side / 6)));
      const int cx = static_cast<int>(rng.range(r, w - 1 - r));
      const int cy = static_cast<int>(rng.range(r, h - 1 - r));
      bx0 = cx - r;
      by0 = cy - r;
      bw = bh = 2 * r + 1;
      o.r = r;
      o.cx = cx + o.shift_x;
      o.cy = cy + o.shift_y;
    }
    o.tex = make_texture(bx0, by0, bw + 1, bh, rng);
    surfaces.push_back(std::move(o));
  }

  // One slanted rectangle in front of the background.
  {
    SplitMix64 rng(stream_seed(p.seed, 1 + kObjects));
    Surface o;
    o.shape = Shape::kRect;
    const int bw = static_cast<int>(rng.range(w / 5, w / 3));
    const int bh = static_cast<int>(rng.range(h / 5, h / 3));
    const int bx0 = static_cast<int>(rng.range(0, w - bw));
    const int by0 = static_cast<int>(rng.range(0, h - bh));
    const std::int64_t vx = rng.range(-3, 3), vy = rng.range(-2, 2);
    o.shift_x = vx * p.frame;
    o.shift_y = vy * p.frame;
    // Disparities over the rectangle stay in [bg_hi + 1, nd - 1]: the total
    // variation is at most half of that span, the offset takes the rest.
    const std::int64_t span = (nd - 1 - (bg_hi + 1)) * kOne;
    const std::int64_t bmax = std::min<std::int64_t>(kOne / 8, span / 4 / bw);
    const std::int64_t cmax = std::min<std::int64_t>(kOne / 8, span / 4 / bh);
    const std::int64_t b = rng.range(-bmax, bmax), c = rng.range(-cmax, cmax);
    const std::int64_t tv = (b < 0 ? -b : b) * (bw - 1) + (c < 0 ? -c : c) * (bh - 1);
    const std::int64_t lo = (bg_hi + 1) * kOne + rng.range(0, std::max<std::int64_t>(0, span - tv));
    // Plane in frame-0 rectangle coordinates: minimum at the lowest corner = lo.
    const std::int64_t a0 = lo - std::min<std::int64_t>(0, b * (bw - 1)) -
                            std::min<std::int64_t>(0, c * (bh - 1)) - b * bx0 - c * by0;
    o.b = b;
    o.c = c;
    // Moving the rectangle moves its plane with it.
    o.a = a0 - b * o.shift_x - c * o.shift_y;
    o.x0 = bx0 + o.shift_x;
    o.y0 = by0 + o.shift_y;
    o.x1 = o.x0 + bw - 1;
    o.y1 = o.y0 + bh - 1;
    o.tex = make_texture(bx0, by0, bw + 1, bh, rng);
    surfaces.push_back(std::move(o));
  }
  return render(surfaces, w, h);
}

}  // namespace tristereo
