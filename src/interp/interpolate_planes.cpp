#include "src/interp/interpolate_planes.hpp"

#include <algorithm>
#include <string>

#include "src/interp/small_triangles.hpp"
#include "src/tritree/fill_rule.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

namespace {

// Fills [x_begin, x_end) of one row with floor(num(x) / den), num(x) linear in x.
// num(x_begin) = q den + r with 0 <= r < den; each step adds step = sq den + sr
// (0 <= sr < den), carrying r into q: exact, one compare per pixel.
void fill_span(std::int16_t* out, int x_begin, int x_end, std::int64_t num, std::int64_t step,
               std::int64_t den) {
  std::int64_t q = floor_div(num, den);
  if (x_end - x_begin == 1) {  // most spans of a fine mesh: skip the step's division
    out[x_begin] = static_cast<std::int16_t>(q);
    return;
  }
  std::int64_t r = num - q * den;
  const std::int64_t sq = floor_div(step, den);
  const std::int64_t sr = step - sq * den;
  for (int x = x_begin; x < x_end; ++x) {
    out[x] = static_cast<std::int16_t>(q);
    q += sq;
    r += sr;
    if (r >= den) {
      r -= den;
      ++q;
    }
  }
}

// Triangles up to this area2 take the shift path in int32: inside a triangle
// N / area2 lies between its vertex disparities (|d| < 2^15), so
// |2 N + area2| < 2^29 and one more step (|2 n_x| < 2^25) still fits.
constexpr std::int64_t kMaxShiftArea2 = 4096;

// [x_begin, x_end) of one row with num(x) >> shift, num(x_begin) = num,
// num(x + 1) = num(x) + step: floor(num / 2^shift), exact. No carry, so
// the compiler vectorises it across x.
void fill_span_shift(std::int16_t* out, int x_begin, int x_end, std::int32_t num, std::int32_t step,
                     int shift) {
  for (int x = x_begin; x < x_end; ++x) {
    out[x] = static_cast<std::int16_t>(num >> shift);
    num += step;
  }
}

}  // namespace

namespace {

// One triangle; inlined into interpolate_triangles' loop.
inline void plane_of_triangle(const SmallTriangleMasks& masks, const Vertex& a, const Vertex& b, const Vertex& c,
                              std::int16_t disp_a, std::int16_t disp_b, std::int16_t disp_c,
                              ImageView<std::int16_t> disp_q4) {
  const int w = disp_q4.width, h = disp_q4.height;
  const std::int64_t da = disp_a, db = disp_b, dc = disp_c;
  const std::int64_t ux = b.x - a.x, uy = b.y - a.y, ud = db - da;
  const std::int64_t vx = c.x - a.x, vy = c.y - a.y, vd = dc - da;
  const std::int64_t area2 = ux * vy - uy * vx;  // n_I
  if (area2 <= 0) return;                        // not a mesh triangle (precondition)

  if (da == kInvalidDispQ4 || db == kInvalidDispQ4 || dc == kInvalidDispQ4) {
    for_each_owned_span(a, b, c, w, h, [&](int y, int x0, int x1) {
      std::int16_t* row = disp_q4.row(y);
      for (int x = x0; x < x1; ++x) row[x] = kInvalidDispQ4;
    });
    return;
  }
  const std::int64_t nx = uy * vd - ud * vy;
  const std::int64_t ny = ud * vx - ux * vd;
  const bool small = ux >= -2 && ux <= 2 && uy >= -2 && uy <= 2 && vx >= -2 && vx <= 2 &&
                     vy >= -2 && vy <= 2 && std::max({a.x, b.x, c.x}) < w - 1 &&
                     std::max({a.y, b.y, c.y}) < h - 1;
  if (small && (area2 & (area2 - 1)) == 0) {
    // Few pixels, known from the table: evaluate each one directly.
    std::uint32_t m = masks.mask[small_key(static_cast<int>(ux), static_cast<int>(uy),
                                           static_cast<int>(vx), static_cast<int>(vy))];
    const int shift = __builtin_ctzll(static_cast<unsigned long long>(area2)) + 1;
    const std::int64_t base = 2 * area2 * da + area2;
    while (m != 0) {
      const int bit = __builtin_ctz(m);
      m &= m - 1;
      const int dy = bit / 5 - 2, dx = bit % 5 - 2;
      disp_q4.row(a.y + dy)[a.x + dx] = static_cast<std::int16_t>((base - 2 * (nx * dx + ny * dy)) >> shift);
    }
    return;
  }
  if (area2 <= kMaxShiftArea2 && (area2 & (area2 - 1)) == 0) {
    // The tritree's triangles (all but the stretched ones on the image's
    // last row and column) have area2 = 2^k: the rounded quotient is a shift.
    const int shift = __builtin_ctzll(static_cast<unsigned long long>(area2)) + 1;
    const std::int32_t step = static_cast<std::int32_t>(-2 * nx);
    for_each_owned_span(a, b, c, w, h, [&](int y, int x0, int x1) {
      const std::int64_t n0 = area2 * da - nx * (x0 - a.x) - ny * (y - a.y);
      fill_span_shift(disp_q4.row(y), x0, x1, static_cast<std::int32_t>(2 * n0 + area2), step, shift);
    });
    return;
  }
  // Rounded value = floor(num / den) with num = 2 N + area2, den = 2 area2;
  // N falls by n_x per pixel to the right.
  const std::int64_t den = 2 * area2;
  for_each_owned_span(a, b, c, w, h, [&](int y, int x0, int x1) {
    const std::int64_t n0 = area2 * da - nx * (x0 - a.x) - ny * (y - a.y);
    fill_span(disp_q4.row(y), x0, x1, 2 * n0 + area2, -2 * nx, den);
  });
}

}  // namespace

void interpolate_triangle(const Vertex& a, const Vertex& b, const Vertex& c, std::int16_t disp_a,
                          std::int16_t disp_b, std::int16_t disp_c, ImageView<std::int16_t> disp_q4) {
  plane_of_triangle(small_triangle_masks(), a, b, c, disp_a, disp_b, disp_c, disp_q4);
}

void interpolate_triangles(const Mesh& mesh, const std::int16_t* vertex_disp_q4,
                           int tri_begin, int tri_end, ImageView<std::int16_t> disp_q4) {
  const int w = mesh.width, h = mesh.height;
  if (disp_q4.data == nullptr || vertex_disp_q4 == nullptr)
    throw Error(ErrorCode::kInvalidArgument, "interpolate_triangles: null buffer");
  if (disp_q4.width != w || disp_q4.height != h || disp_q4.channels != 1)
    throw Error(ErrorCode::kSizeMismatch,
                "disparity map is " + std::to_string(disp_q4.width) + "x" +
                    std::to_string(disp_q4.height) + "x" + std::to_string(disp_q4.channels) +
                    ", the mesh is " + std::to_string(w) + "x" + std::to_string(h) + "x1");
  if (disp_q4.stride_bytes < static_cast<std::ptrdiff_t>(sizeof(std::int16_t)) * w)
    throw Error(ErrorCode::kInvalidArgument,
                "disparity map stride " + std::to_string(disp_q4.stride_bytes) +
                    " bytes is below width * 2 = " + std::to_string(2 * w));
  const int n_tri = static_cast<int>(mesh.triangles.size());
  if (tri_begin < 0 || tri_end > n_tri || tri_begin > tri_end)
    throw Error(ErrorCode::kInvalidArgument,
                "triangle range [" + std::to_string(tri_begin) + ", " + std::to_string(tri_end) +
                    ") is not inside [0, " + std::to_string(n_tri) + "]");

  const SmallTriangleMasks& masks = small_triangle_masks();
  for (int t = tri_begin; t < tri_end; ++t) {
    const Triangle& tri = mesh.triangles[static_cast<std::size_t>(t)];
    plane_of_triangle(masks, mesh.vertices[static_cast<std::size_t>(tri[0])],
                         mesh.vertices[static_cast<std::size_t>(tri[1])],
                         mesh.vertices[static_cast<std::size_t>(tri[2])], vertex_disp_q4[tri[0]],
                         vertex_disp_q4[tri[1]], vertex_disp_q4[tri[2]], disp_q4);
  }
}

}  // namespace tristereo
