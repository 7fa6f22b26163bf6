#include "src/interp/interpolate_midpoints.hpp"

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <type_traits>

#include "src/interp/interpolate_planes.hpp"
#include "src/kernels/kernel_set.hpp"
#include "src/tritree/fill_rule.hpp"
#include "tristereo/fixed_point.hpp"

namespace tristereo {

namespace {

// Not yet known: a grid point that is not a vertex.
constexpr std::int32_t kUnknown = kMidpointUnknown;

// (a + b) / 2 of two known values (exact: their sum is even); garbage, without
// overflow, when one is kUnknown (the caller then keeps its own value).
inline std::int32_t midpoint(std::int32_t a, std::int32_t b) {
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) + static_cast<std::uint32_t>(b)) >> 1;
}

// The grid point i from ia and ib, the points it averages, when unknown
// (indices into `values`); with kConf, its confidence too (the same indices
// into `conf`): the smaller of theirs. Whether a grid point is a vertex is
// close to a coin toss, so the choice is a mask, not a branch (the compiler
// made it a branch).
template <bool kConf>
inline void resolve(std::int32_t* values, std::uint8_t* conf, std::ptrdiff_t i, std::ptrdiff_t ia,
                    std::ptrdiff_t ib) {
  const std::int32_t m = midpoint(values[ia], values[ib]), old = values[i];
  const std::int32_t unknown = -static_cast<std::int32_t>(old == kUnknown);  // all ones or zero
  values[i] = (m & unknown) | (old & ~unknown);
  if constexpr (kConf) {
    const std::int32_t c = std::min(conf[ia], conf[ib]);
    conf[i] = static_cast<std::uint8_t>((c & unknown) | (conf[i] & ~unknown));
  }
}

}  // namespace

namespace {

// Square centres, then side midpoints, at level s, then the levels below
// down to side 4, of the tile whose corner is values[0] (rows `n` apart;
// with kConf its confidences from conf[0], laid out alike; s and S known at
// compile time: the short rows unroll).
template <int S, int s, bool kConf>
inline void resolve_levels(std::int32_t* values, std::uint8_t* conf, std::ptrdiff_t n, int x0, int y0, int nx,
                           int ny) {
  static_assert(s >= 4, "side 2 goes along whole rows (resolve_level2)");
  constexpr int h = s / 2;
  for (int j = 0; j + h <= ny; j += s) {
    const std::ptrdiff_t top = j * n, bottom = top + s * n, centre = (j + h) * n + h;
    // The diagonals alternate along a row of squares.
    bool bs = RtinLayout::backslash(x0, y0 + j, s);
    for (int i = 0; i + h <= nx; i += s, bs = !bs) {
      if (bs) resolve<kConf>(values, conf, centre + i, top + i, bottom + i + s);
      else resolve<kConf>(values, conf, centre + i, top + i + s, bottom + i);
    }
  }
  for (int j = 0; j <= ny; j += s) {  // horizontal sides
    const std::ptrdiff_t r = j * n;
    for (int i = h; i <= nx; i += s) resolve<kConf>(values, conf, r + i, r + i - h, r + i + h);
  }
  for (int j = h; j <= ny; j += s) {  // vertical sides
    const std::ptrdiff_t r = j * n;
    for (int i = 0; i <= nx; i += s) resolve<kConf>(values, conf, r + i, r + i - h * n, r + i + h * n);
  }
  if constexpr (s > 4) resolve_levels<S, s / 2, kConf>(values, conf, n, x0, y0, nx, ny);
}

// A row of tiles at a time: its grid values in one buffer (S + 1 rows of the
// virtual width), so every vertex of its rows is placed by one walk along the
// row's vertices (a walk per tile row and tile ended at a data-dependent
// vertex: a mispredicted exit for every tile row of every tile). Tiles side
// by side share their common column, which both resolve alike. With kConf
// the confidences go along, a byte per point after the values' band (never
// cleared: every point whose confidence a kept result reads is written
// first, as its value is).
template <int S, bool kConf>
bool midpoint_tiles(const TritreeGrid& grid, const Mesh& mesh, const std::int16_t* vertex_disp_q4,
                    int tile_row_begin, int tile_row_end, const KernelSet& kernels, std::int32_t* scratch,
                    ImageView<std::int16_t> disp_q4, const ConfidenceMaps* conf) {
  const RtinLayout& L = grid.layout;
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(L.vw) + 1;
  // One point before the grid's first: the side-2 kernel reads x = -1.
  std::int32_t* const values = scratch + 1;
  const int F = midpoint_fraction_bits(S);
  const std::int32_t one = std::int32_t{1} << F;
  const Vertex* vertices = mesh.vertices.data();
  const int last_x = L.width - 1;
  // conf[i] is the confidence of values[i] (from i = -1 too).
  std::uint8_t* const conf_values =
      kConf ? reinterpret_cast<std::uint8_t*>(scratch + midpoint_band_values(S, L.width)) + 1 : nullptr;
  const std::uint8_t* vertex_conf = kConf ? conf->vertex_confidence : nullptr;
  unsigned invalid = 0;
  for (int ty = tile_row_begin; ty < tile_row_end; ++ty) {
    const int y0 = ty * S;
    const int ny = std::min(S, L.vh - y0);  // last local row
    // Every row, and S points past the last: a partial tile's crossing
    // squares (whose centres are vertices) read past the grid's last row
    // and column.
    std::memset(scratch, kMidpointUnknownByte, static_cast<std::size_t>(values + (S + 1) * n + S - scratch) * sizeof(*scratch));
    // The vertices' samples: each row's vertices are consecutive ids. The
    // last real column is on the grid's last, vw (the same column unless
    // the side is stretched, when real x = vw is no grid point).
    for (int j = 0; j <= ny; ++j) {
      const std::size_t y = static_cast<std::size_t>(L.real_y(y0 + j));
      std::int32_t* v = values + j * n;
      const std::int32_t end = mesh.row_start[y + 1];
      for (std::int32_t id = mesh.row_start[y]; id < end; ++id) {
        const int x = vertices[id].x;
        const int gx = x == last_x ? L.vw : x;
        v[gx] = vertex_disp_q4[id] * one;
        if constexpr (kConf) conf_values[j * n + gx] = vertex_conf[id];
      }
    }
    // Apart, so that it vectorises: whether any of them is invalid.
    const std::int32_t first_id = mesh.row_start[static_cast<std::size_t>(L.real_y(y0))];
    const std::int32_t end_id = mesh.row_start[static_cast<std::size_t>(L.real_y(y0 + ny)) + 1];
    for (std::int32_t id = first_id; id < end_id; ++id)
      invalid |= static_cast<unsigned>(vertex_disp_q4[id] == kInvalidDispQ4);
    // Each tile from its side down to side 4, then side 2 along the rows.
    if constexpr (S >= 4) {
      for (int tx = 0; tx < L.tiles_x; ++tx) {
        const int x0 = tx * S;
        resolve_levels<S, S, kConf>(values + x0, kConf ? conf_values + x0 : nullptr, n, x0, y0, std::min(S, L.vw - x0), ny);
      }
    }
    // Side 2 (three quarters of the grid points, each the average of two
    // points of even coordinates, all known now) and the rounding to Q4, a
    // row at a time: the row of tiles' half-open rows, the grid's last row
    // too, and its last column (on the moved line when the side is
    // stretched; x = vw is even, so the kernel's x = 0 rule is its own).
    const int jn = y0 + ny == L.vh ? ny : ny - 1;
    for (int j = 0; j <= jn; ++j) {
      std::int16_t* out = disp_q4.row(L.real_y(y0 + j));
      const std::int32_t* v = values + j * n;
      const bool odd = (j & 1) != 0;
      const std::int32_t* above = odd ? v - n : nullptr;
      const std::int32_t* below = odd ? v + n : nullptr;
      // The 2 x 2 squares' diagonals alternate along the row, '\' first when
      // (0, y0 + j - 1) is a '\' corner.
      const int first_bs = odd && RtinLayout::backslash(0, y0 + j - 1, 2) ? 1 : 0;
      const int xl = L.real_x(L.vw);
      if constexpr (kConf) {
        const int yr = L.real_y(y0 + j);
        std::uint8_t* c = conf->confidence.row(yr);
        std::uint8_t* st = conf->state.row(yr);
        const std::uint8_t* cv = conf_values + j * n;
        const std::uint8_t* ca = odd ? cv - n : nullptr;
        const std::uint8_t* cb = odd ? cv + n : nullptr;
        kernels.midpoints_row_conf_q4(above, v, below, ca, cv, cb, L.vw, first_bs, F, out, c, st);
        kernels.midpoints_row_conf_q4(odd ? above + L.vw : nullptr, v + L.vw, odd ? below + L.vw : nullptr,
                                      odd ? ca + L.vw : nullptr, cv + L.vw, odd ? cb + L.vw : nullptr, 1, 0, F,
                                      out + xl, c + xl, st + xl);
      } else {
        kernels.midpoints_row_q4(above, v, below, L.vw, first_bs, F, out);
        kernels.midpoints_row_q4(odd ? above + L.vw : nullptr, v + L.vw, odd ? below + L.vw : nullptr, 1, 0, F,
                                 out + xl);
      }
    }
  }
  return invalid != 0;
}

}  // namespace

bool interpolate_midpoint_tiles(const TritreeGrid& grid, const Mesh& mesh, const std::int16_t* vertex_disp_q4,
                                int tile_row_begin, int tile_row_end, const KernelSet& kernels,
                                std::int32_t* scratch, ImageView<std::int16_t> disp_q4, const ConfidenceMaps* conf) {
  const auto run = [&](auto tile) {
    constexpr int S = decltype(tile)::value;
    if (conf != nullptr)
      return midpoint_tiles<S, true>(grid, mesh, vertex_disp_q4, tile_row_begin, tile_row_end, kernels, scratch,
                                     disp_q4, conf);
    return midpoint_tiles<S, false>(grid, mesh, vertex_disp_q4, tile_row_begin, tile_row_end, kernels, scratch,
                                    disp_q4, conf);
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
                                  const std::int16_t* vertex_disp_q4, std::size_t leaf_begin,
                                  std::size_t leaf_end, ImageView<std::int16_t> disp_q4,
                                  const ConfidenceMaps* conf) {
  for (std::size_t t = leaf_begin; t < std::min(leaf_end, grid.stretched_count); ++t) {
    const Triangle& tri = grid.stretched[t];
    const Vertex& a = mesh.vertices[static_cast<std::size_t>(tri[0])];
    const Vertex& b = mesh.vertices[static_cast<std::size_t>(tri[1])];
    const Vertex& c = mesh.vertices[static_cast<std::size_t>(tri[2])];
    const std::int16_t da = vertex_disp_q4[tri[0]], db = vertex_disp_q4[tri[1]], dc = vertex_disp_q4[tri[2]];
    interpolate_triangle(a, b, c, da, db, dc, disp_q4);
    if (conf != nullptr)
      confidence_triangle(a, b, c, conf->vertex_confidence[tri[0]], conf->vertex_confidence[tri[1]],
                          conf->vertex_confidence[tri[2]],
                          da == kInvalidDispQ4 || db == kInvalidDispQ4 || dc == kInvalidDispQ4, *conf);
  }
}

void invalidate_triangles(const Mesh& mesh, const std::int16_t* vertex_disp_q4, int tri_begin,
                          int tri_end, ImageView<std::int16_t> disp_q4, const ConfidenceMaps* conf) {
  for (int t = tri_begin; t < tri_end; ++t) {
    const Triangle& tri = mesh.triangles[static_cast<std::size_t>(t)];
    const std::int16_t da = vertex_disp_q4[tri[0]], db = vertex_disp_q4[tri[1]], dc = vertex_disp_q4[tri[2]];
    if (da != kInvalidDispQ4 && db != kInvalidDispQ4 && dc != kInvalidDispQ4) continue;
    const Vertex& a = mesh.vertices[static_cast<std::size_t>(tri[0])];
    const Vertex& b = mesh.vertices[static_cast<std::size_t>(tri[1])];
    const Vertex& c = mesh.vertices[static_cast<std::size_t>(tri[2])];
    if (conf == nullptr) {
      interpolate_triangle(a, b, c, da, db, dc, disp_q4);
      continue;
    }
    // One walk for the three maps (spans of a pixel or two: no memset calls).
    for_each_owned_span(a, b, c, disp_q4.width, disp_q4.height, [&](int y, int x0, int x1) {
      std::int16_t* d = disp_q4.row(y);
      std::uint8_t* cf = conf->confidence.row(y);
      std::uint8_t* st = conf->state.row(y);
      for (int x = x0; x < x1; ++x) {
        d[x] = kInvalidDispQ4;
        cf[x] = 0;
        st[x] = 0;
      }
    });
  }
}

}  // namespace tristereo
