// The split criterion: area test, then the plane-fit (PSNR) test on exact sums.
#include "src/tritree/tritree_criterion.hpp"

#include <algorithm>
#include <cstdlib>

#include "src/tritree/fill_rule.hpp"
#include "src/tritree/plane_residual.hpp"
#include "src/tritree/tritree_geometry.hpp"

namespace tristereo {

namespace {

// Upper bound on the pixels a triangle owns: they are lattice points of the
// closed triangle, which Pick's theorem counts as area + B/2 + 1 with B (the
// lattice points on the boundary) <= the sum of max(|dx|, |dy|) over the edges.
std::int64_t owned_pixels_upper_bound(const Vertex& a, const Vertex& b, const Vertex& c,
                                      std::int64_t area2) {
  const auto steps = [](const Vertex& p, const Vertex& q) {
    return std::max(std::abs(q.x - p.x), std::abs(q.y - p.y));
  };
  return (area2 + steps(a, b) + steps(b, c) + steps(c, a)) / 2 + 1;
}

}  // namespace

bool tritree_wants_split(ImageView<const std::uint8_t> gray, const Vertex& a, const Vertex& b,
                         const Vertex& c, int max_area_px2, std::uint64_t mse_q8) {
  const std::int64_t area2 = area2_of(a, b, c);
  if (area2 > 2 * std::int64_t{max_area_px2}) return true;

  // n = u x v with u = B - A, v = C - A in (x, y, I); n_I == area2.
  const std::int64_t ia = gray.row(a.y)[a.x];
  const std::int64_t ux = b.x - a.x, uy = b.y - a.y, ui = gray.row(b.y)[b.x] - ia;
  const std::int64_t vx = c.x - a.x, vy = c.y - a.y, vi = gray.row(c.y)[c.x] - ia;
  const std::int64_t n_x = uy * vi - ui * vy;
  const std::int64_t n_y = ui * vx - ux * vi;

  // Split  <=>  SSE * 256 > mse_q8 * n_px * area2^2  <=>  SSE > floor(limit / 256)
  // (integers; limit < 2^58, docs/model.md section 5). n_px is only known
  // after the last row, so the walk stops early against the cap of an upper
  // bound of n_px: a partial SSE above it proves the full test true (row sums
  // are >= 0). Otherwise the exact test runs on the complete sums. One walk
  // over the rows instead of a counting walk plus an SSE walk: most
  // triangles that split stop after a few rows.
  const std::uint64_t a2_sq = static_cast<std::uint64_t>(area2 * area2);
  const std::uint64_t early_cap =
      (mse_q8 * static_cast<std::uint64_t>(owned_pixels_upper_bound(a, b, c, area2)) * a2_sq) >> 8;
  const int w = gray.width;
  const int h = gray.height;
  using fill_rule_detail::EdgeRows;
  const int y_lo = std::min({a.y, b.y, c.y});
  const int y_hi = std::max({a.y, b.y, c.y});
  EdgeRows ab(a, b, y_lo), bc(b, c, y_lo), ca(c, a, y_lo);
  std::int64_t n_px = 0;
  std::uint64_t sse = 0;
  for (int y = y_lo; y <= y_hi; ++y) {
    std::int32_t x0 = 0;
    std::int32_t x1 = w;
    ab.clip(y, w, h, x0, x1);
    bc.clip(y, w, h, x0, x1);
    ca.clip(y, w, h, x0, x1);
    if (x0 < x1) {
      n_px += x1 - x0;
      const std::int64_t r0 = n_x * (x0 - a.x) + n_y * (y - a.y) - area2 * ia;
      sse += plane_residual_sse_span_inline(gray.row(y), x0, x1, r0, n_x, area2);
      if (sse > early_cap) return true;
    }
    ab.next_row();
    bc.next_row();
    ca.next_row();
  }
  return sse > ((mse_q8 * static_cast<std::uint64_t>(n_px) * a2_sq) >> 8);
}

}  // namespace tristereo
