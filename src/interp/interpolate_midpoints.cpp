#include "src/interp/interpolate_midpoints.hpp"

#include <algorithm>
#include <type_traits>

#include "src/interp/interpolate_planes.hpp"
#include "tristereo/fixed_point.hpp"

namespace tristereo {

namespace {

// Not yet known (a grid point that is not a vertex): below every value,
// vertex values are |16 d * 2^F| < 2^27.
constexpr std::int32_t kUnknown = INT32_MIN;

// (a + b) / 2 of two known values (exact: their sum is even); garbage, without
// overflow, when one is kUnknown (the caller then keeps its own value).
inline std::int32_t midpoint(std::int32_t a, std::int32_t b) {
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) + static_cast<std::uint32_t>(b)) >> 1;
}

// Whether a grid point is a vertex is close to a coin toss, so the choice is
// a mask, not a branch (the compiler made it a branch).
inline void resolve(std::int32_t* v, std::int32_t a, std::int32_t b) {
  const std::int32_t m = midpoint(a, b), old = *v;
  const std::int32_t unknown = -static_cast<std::int32_t>(old == kUnknown);  // all ones or zero
  *v = (m & unknown) | (old & ~unknown);
}

}  // namespace

namespace {

// Square centres, then side midpoints, at level s, then the levels below (s
// and S known at compile time: the strides fold and the short rows unroll).
template <int S, int s>
inline void resolve_levels(std::int32_t* values, int x0, int y0, int nx, int ny) {
  constexpr int n = S + 1, h = s / 2;
  for (int j = 0; j + h <= ny; j += s) {
    const std::int32_t* top = values + j * n;
    const std::int32_t* bottom = top + s * n;
    std::int32_t* centre = values + (j + h) * n + h;
    // The diagonals alternate along a row of squares.
    bool bs = RtinLayout::backslash(x0, y0 + j, s);
    for (int i = 0; i + h <= nx; i += s, bs = !bs) {
      if (bs) resolve(centre + i, top[i], bottom[i + s]);
      else resolve(centre + i, top[i + s], bottom[i]);
    }
  }
  for (int j = 0; j <= ny; j += s) {  // horizontal sides
    std::int32_t* v = values + j * n;
    for (int i = h; i <= nx; i += s) resolve(v + i, v[i - h], v[i + h]);
  }
  for (int j = h; j <= ny; j += s) {  // vertical sides
    std::int32_t* v = values + j * n;
    for (int i = 0; i <= nx; i += s) resolve(v + i, v[i - h * n], v[i + h * n]);
  }
  if constexpr (s > 2) resolve_levels<S, s / 2>(values, x0, y0, nx, ny);
}

template <int S>
bool midpoint_tiles(const TritreeGrid& grid, const Mesh& mesh, const std::int16_t* vertex_disp_q4,
                    int tile_row_begin, int tile_row_end, std::int32_t* values, ImageView<std::int16_t> disp_q4) {
  const RtinLayout& L = grid.layout;
  constexpr int n = S + 1;
  const int F = midpoint_fraction_bits(S);
  const std::int32_t one = std::int32_t{1} << F, half = one >> 1;
  const Vertex* vertices = mesh.vertices.data();
  // Per local row, the first vertex of the row not left of the current tile.
  std::int32_t* cursor = values + static_cast<std::size_t>(n) * n;
  unsigned invalid = 0;
  for (int ty = tile_row_begin; ty < tile_row_end; ++ty) {
    const int y0 = ty * S;
    const int ny = std::min(S, L.vh - y0);  // last local row
    for (int j = 0; j <= ny; ++j) cursor[j] = mesh.row_start[static_cast<std::size_t>(L.real_y(y0 + j))];
    for (int tx = 0; tx < L.tiles_x; ++tx) {
      const int x0 = tx * S;
      const int nx = std::min(S, L.vw - x0);
      std::fill(values, values + static_cast<std::size_t>(n) * n, kUnknown);
      // The vertices' samples: each row's vertices are consecutive ids in x
      // order; a tile's last column is the next tile's first.
      for (int j = 0; j <= ny; ++j) {
        const std::int32_t end = mesh.row_start[static_cast<std::size_t>(L.real_y(y0 + j)) + 1];
        std::int32_t* v = values + j * n;
        for (std::int32_t id = cursor[j]; id < end; ++id) {
          const int x = vertices[id].x;
          const int vx = (L.stretch_x && x == L.width - 1) ? L.vw : x;
          if (vx > x0 + S) break;
          v[vx - x0] = vertex_disp_q4[id] * one;
          invalid |= static_cast<unsigned>(vertex_disp_q4[id] == kInvalidDispQ4);
          if (vx < x0 + S) cursor[j] = id + 1;
        }
      }
      // From the tile down to side 2.
      resolve_levels<S, S>(values, x0, y0, nx, ny);
      // Rounded to Q4, half up. Each tile writes its half-open square, the
      // grid's last tiles their closing column and row too (on the moved
      // line when the side is stretched).
      const int jn = y0 + ny == L.vh ? ny : ny - 1;
      const bool last_column = x0 + nx == L.vw;
      for (int j = 0; j <= jn; ++j) {
        std::int16_t* out = disp_q4.row(L.real_y(y0 + j));
        const std::int32_t* v = values + j * n;
        for (int i = 0; i < nx; ++i) out[x0 + i] = static_cast<std::int16_t>((v[i] + half) >> F);
        if (last_column) out[L.real_x(L.vw)] = static_cast<std::int16_t>((v[nx] + half) >> F);
      }
    }
  }
  return invalid != 0;
}

}  // namespace

bool interpolate_midpoint_tiles(const TritreeGrid& grid, const Mesh& mesh, const std::int16_t* vertex_disp_q4,
                                int tile_row_begin, int tile_row_end, std::int32_t* values,
                                ImageView<std::int16_t> disp_q4) {
  const auto run = [&](auto tile) {
    return midpoint_tiles<decltype(tile)::value>(grid, mesh, vertex_disp_q4, tile_row_begin, tile_row_end, values,
                                                 disp_q4);
  };
  switch (grid.layout.tile) {  // powers of two 2 .. 64 (A_max <= 1024)
    case 2: return run(std::integral_constant<int, 2>{});
    case 4: return run(std::integral_constant<int, 4>{});
    case 8: return run(std::integral_constant<int, 8>{});
    case 16: return run(std::integral_constant<int, 16>{});
    case 32: return run(std::integral_constant<int, 32>{});
    default: return run(std::integral_constant<int, 64>{});
  }
}

void interpolate_stretched_leaves(const TritreeGrid& grid, const Mesh& mesh,
                                  const std::int16_t* vertex_disp_q4, ImageView<std::int16_t> disp_q4) {
  for (std::size_t t = 0; t < grid.stretched_count; ++t) {
    const Triangle& tri = grid.stretched[t];
    interpolate_triangle(mesh.vertices[static_cast<std::size_t>(tri[0])],
                         mesh.vertices[static_cast<std::size_t>(tri[1])],
                         mesh.vertices[static_cast<std::size_t>(tri[2])], vertex_disp_q4[tri[0]],
                         vertex_disp_q4[tri[1]], vertex_disp_q4[tri[2]], disp_q4);
  }
}

void invalidate_triangles(const Mesh& mesh, const std::int16_t* vertex_disp_q4, int tri_begin,
                          int tri_end, ImageView<std::int16_t> disp_q4) {
  for (int t = tri_begin; t < tri_end; ++t) {
    const Triangle& tri = mesh.triangles[static_cast<std::size_t>(t)];
    const std::int16_t da = vertex_disp_q4[tri[0]], db = vertex_disp_q4[tri[1]], dc = vertex_disp_q4[tri[2]];
    if (da != kInvalidDispQ4 && db != kInvalidDispQ4 && dc != kInvalidDispQ4) continue;
    interpolate_triangle(mesh.vertices[static_cast<std::size_t>(tri[0])],
                         mesh.vertices[static_cast<std::size_t>(tri[1])],
                         mesh.vertices[static_cast<std::size_t>(tri[2])], da, db, dc, disp_q4);
  }
}

}  // namespace tristereo
