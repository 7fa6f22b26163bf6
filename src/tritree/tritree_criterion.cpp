// The split criterion: area test, then the plane-fit (PSNR) test on exact sums.
#include "src/tritree/tritree_criterion.hpp"

#include "src/tritree/fill_rule.hpp"
#include "src/tritree/plane_residual.hpp"
#include "src/tritree/tritree_geometry.hpp"

namespace tristereo {

bool tritree_wants_split(ImageView<const std::uint8_t> gray, const Vertex& a, const Vertex& b,
                         const Vertex& c, int max_area_px2, std::uint64_t mse_q8) {
  const std::int64_t area2 = area2_of(a, b, c);
  if (area2 > 2 * std::int64_t{max_area_px2}) return true;

  const int w = gray.width;
  const int h = gray.height;
  // Pixel count first (spans only, cheap), so the SSE loop can stop early.
  std::int64_t n_px = 0;
  for_each_owned_span(a, b, c, w, h, [&](int, int x0, int x1) { n_px += x1 - x0; });
  if (n_px == 0) return false;  // SSE = 0 cannot exceed the bound

  // n = u x v with u = B - A, v = C - A in (x, y, I); n_I == area2.
  const std::int64_t ia = gray.row(a.y)[a.x];
  const std::int64_t ux = b.x - a.x, uy = b.y - a.y, ui = gray.row(b.y)[b.x] - ia;
  const std::int64_t vx = c.x - a.x, vy = c.y - a.y, vi = gray.row(c.y)[c.x] - ia;
  const std::int64_t n_x = uy * vi - ui * vy;
  const std::int64_t n_y = ui * vx - ux * vi;

  // SSE * 256 > limit  <=>  SSE > floor(limit / 256) for integer SSE.
  // limit < 2^58 (docs/model.md section 5).
  const std::uint64_t limit = mse_q8 * static_cast<std::uint64_t>(n_px) *
                              static_cast<std::uint64_t>(area2 * area2);
  const std::uint64_t sse_cap = limit >> 8;
  std::uint64_t sse = 0;
  bool over = false;
  for_each_owned_span(a, b, c, w, h, [&](int y, int x0, int x1) {
    if (over) return;
    const std::int64_t r0 = n_x * (x0 - a.x) + n_y * (y - a.y) - area2 * ia;
    sse += plane_residual_sse_span_scalar(gray.row(y), x0, x1, r0, n_x, area2);
    over = sse > sse_cap;
  });
  return over;
}

}  // namespace tristereo
