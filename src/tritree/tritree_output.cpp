// Tritree output: the mesh in its canonical form (include/tristereo/mesh.hpp)
// from the leaves: vertex ids by one scan of the vertex marks; the triangles,
// rotated to their smallest id as pass 3 emits them, are already in the
// hierarchy's order, and each row of tiles writes them straight into its
// place: the scan also counts them (Euler's formula, count_vertices()).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "platform/clock.hpp"
#include "platform/thread_pool.hpp"
#include "platform/work_chunks.hpp"
#include "src/tritree/tritree.hpp"

namespace tristereo {

// Vertices: every corner of a leaf is a tile corner or the midpoint of a
// split triangle, i.e. a grid point with need(m) (need(m) implies that every
// ancestor split too). So the vertex ids come from a scan of the need grid,
// mapped to real pixels (a monotone map: raster order is kept): each row of
// tiles counts its vertices, the counts' prefix sums give each its first id,
// then each numbers its own rows (both steps on the pool when there is one).

// The vertices of virtual row vy among grid points vx0 .. vx0 + 63 (vx0 a
// multiple of 64), as bits (bit k = point vx0 + k): need bits gathered eight
// at a time (the multiply moves byte k's bit 0 to bit 56 + k of a
// little-endian word, with no carries), plus the tile corners on tile rows
// (S divides 64, so they sit at the same bits in every word). 64 points per
// word, because the loop over a word's bits ends at a data-dependent count:
// one mispredicted exit per 64 points instead of one per 8.
std::uint64_t Tritree::vertex_bits(int vy, int vx0) const {
  const int row_len = layout_.vw + 1, S = tile_;
  const std::uint8_t* need = need_ + static_cast<std::size_t>(vy) * row_len + vx0;
  const int n = std::min(64, row_len - vx0);
  std::uint64_t bits = 0;
  int k = 0;
  for (; k + 8 <= n; k += 8) {
    std::uint64_t word;
    std::memcpy(&word, need + k, 8);
    bits |= (((word & 0x0101010101010101ull) * 0x0102040810204080ull) >> 56) << k;
  }
  for (; k < n; ++k) bits |= static_cast<std::uint64_t>(need[k] & 1u) << k;
  if (vy % S == 0) {  // tile corners are vertices
    std::uint64_t corners = 0;
    for (int c = 0; c < 64; c += S) corners |= std::uint64_t{1} << c;
    bits |= n == 64 ? corners : corners & ((std::uint64_t{1} << n) - 1);
  }
  return bits;
}

// Virtual rows of row of tiles `band`: [band S, next band's first), the last
// one through vh.
void Tritree::band_rows(int band, int* vy0, int* vy1) const {
  *vy0 = band * tile_;
  *vy1 = band + 1 == layout_.tiles_y ? layout_.vh + 1 : (band + 1) * tile_;
}

// Leaves: every triangle lies in one row of tiles, whose leaves triangulate
// its closed rectangle with every vertex on that rectangle's sides a corner
// of the leaves along them (the mesh is conforming). Euler's formula then
// counts them from the vertices alone: T = 2 V - B - 2, with V the vertices
// of the closed rectangle and B those on its sides (its first and last
// rows, and x = 0 or vw on the rows between). So each row of tiles knows
// where its leaves go before pass 3 writes them.
std::size_t Tritree::count_vertices(Mesh& mesh, ThreadPool* pool) {
  const RtinLayout& L = layout_;  // mesh: begin_mesh() done
  const int row_len = L.vw + 1;
  const int bands = L.tiles_y;
  // Each band's count, then its first id.
  std::int32_t* first_id = band_first_id_;
  // A row's vertices: its need bits (a plain byte sum, which the compiler
  // vectorises) plus, on a tile row, the tile corners (never a midpoint, so
  // their need bit is clear).
  const int S = tile_;
  const auto row_vertices = [&](int vy) {
    const std::uint8_t* need = need_ + static_cast<std::size_t>(vy) * row_len;
    std::uint32_t bits = 0;
    for (int x = 0; x < row_len; ++x) bits += need[x] & 1u;
    return static_cast<std::int64_t>(bits) + (vy % S == 0 ? (row_len - 1) / S + 1 : 0);
  };
  const auto count_band = [&](int band) {
    int vy0, vy1;
    band_rows(band, &vy0, &vy1);
    const int vy_last = band + 1 == bands ? L.vh : vy1;  // the closed rectangle's last row
    std::int64_t n = 0, sides = 0;  // rows [vy0, vy1); the rows between's ends
    for (int vy = vy0; vy < vy1; ++vy) {
      n += row_vertices(vy);
      if (vy != vy0 && vy != vy_last) {  // never a tile row: no tile corner
        const std::uint8_t* need = need_ + static_cast<std::size_t>(vy) * row_len;
        sides += (need[0] & 1) + (need[L.vw] & 1);
      }
    }
    const std::int64_t first = row_vertices(vy0), last = row_vertices(vy_last);
    const std::int64_t v = n + (vy_last == vy1 ? last : 0);
    first_id[band] = static_cast<std::int32_t>(n);
    band_start_[band] = static_cast<std::size_t>(2 * v - (first + last + sides) - 2);
  };
  const bool parallel = pool != nullptr && pool->size() > 1 && bands > 1;
  const auto traced_count = [&](int worker, int band) {
    const std::int64_t t0 = trace_ != nullptr ? monotonic_ns() : 0;
    count_band(band);
    if (trace_ != nullptr) trace_->record(worker, TraceKind::kTritreeRows, t0, monotonic_ns(), 3, band);
  };
  if (parallel) {
    // On demand: a worker slowed from outside takes fewer rows of tiles.
    WorkChunks rows;
    rows.reset(0, bands, 1);
    pool->run([&](int worker) {
      int b0 = 0, b1 = 0;
      while (rows.next(&b0, &b1)) traced_count(worker, b0);
    });
  } else {
    for (int band = 0; band < bands; ++band) traced_count(0, band);
  }
  std::int32_t total = 0;
  std::size_t leaves = 0;
  for (int band = 0; band < bands; ++band) {
    const std::int32_t n = first_id[band];
    first_id[band] = total;
    total += n;
    const std::size_t t = band_start_[band];
    band_start_[band] = leaves;
    leaves += t;
  }
  mesh.vertices.resize(static_cast<std::size_t>(total));  // within capacity
  return leaves;
}

// Pass 3 looks up a leaf's corners by position: each row of tiles numbers
// its rows right before it emits, into the mesh and into its worker's rows of
// ids, where they stay in cache (a W x H grid of ids, written by a numbering
// pass of its own, was written and read cold in a frame).
void Tritree::number_band(int band, Mesh& mesh, std::int32_t* ids, Band& b) const {
  const RtinLayout& L = layout_;
  const int w = gray_.width, row_len = L.vw + 1, S = tile_;
  int vy0, vy1;
  band_rows(band, &vy0, &vy1);
  std::int32_t id = band_first_id_[band];
  Vertex* out = mesh.vertices.data();
  const int y0 = L.real_y(vy0);  // never moved: the band's first row is not the grid's last
  int next_y = y0;                // next real row whose row_start is unset
  for (int vy = vy0; vy < vy1; ++vy) {
    const int y = L.real_y(vy);
    for (; next_y <= y; ++next_y) mesh.row_start[static_cast<std::size_t>(next_y)] = id;
    std::int32_t* row_ids = ids + static_cast<std::size_t>(y - y0) * w;
    // Every column is its own but the last, vw (real_x), which the loop
    // leaves for after it: no per-vertex test.
    for (int vx0 = 0; vx0 < row_len; vx0 += 64) {
      std::uint64_t bits = vertex_bits(vy, vx0);
      if (vx0 + 64 >= row_len) bits &= ~(std::uint64_t{1} << (L.vw - vx0));
      for (; bits != 0; bits &= bits - 1) {
        const int x = vx0 + __builtin_ctzll(bits);
        row_ids[x] = id;
        out[id++] = Vertex{x, y};
      }
    }
    if ((vy % S == 0 && L.vw % S == 0) || (need_[static_cast<std::size_t>(vy) * row_len + L.vw] & 1u)) {
      const int x = L.real_x(L.vw);
      row_ids[x] = id;
      out[id++] = Vertex{x, y};
    }
  }
  if (band + 1 == L.tiles_y) {  // the rows after the grid's last
    const auto total = static_cast<std::int32_t>(mesh.vertices.size());
    for (int y = L.real_y(L.vh) + 1; y <= gray_.height; ++y) mesh.row_start[static_cast<std::size_t>(y)] = total;
  }
  b.ids = ids;
  b.ids_y0 = y0;
}

// The next row of tiles' first row (numbered by it: wait for that first)
// into `b`'s ids, after its own rows.
void Tritree::next_first_row_ids(int band, const Mesh& mesh, Band& b) const {
  int vy0, vy1;
  band_rows(band, &vy0, &vy1);
  const auto y = static_cast<std::size_t>(layout_.real_y(vy1));
  std::int32_t* row = b.ids + (y - static_cast<std::size_t>(b.ids_y0)) * static_cast<std::size_t>(gray_.width);
  const Vertex* v = mesh.vertices.data();
  const std::int32_t end = mesh.row_start[y + 1];
  for (std::int32_t id = mesh.row_start[y]; id < end; ++id) row[v[id].x] = id;
}

// A row of tiles' leaves offer to the slots of the vertices of its rows and
// of the next row of tiles' first row (every edge lies in one row of tiles):
// a slot "from above" (even: directions 2, 4, 6) to an edge's lower end, one
// "from below" (odd) to its upper end. So its first row's even slots are the
// row of tiles above's (its edges' lower ends), the next first row's odd
// ones the row of tiles below's: each row of tiles empties the others right
// before it emits, and rows on different workers never write the same slot.
void Tritree::empty_band_slots(int band, const Mesh& mesh) const {
  const auto slots = static_cast<std::size_t>(pred_slots_);
  int vy0, vy1;
  band_rows(band, &vy0, &vy1);
  const auto ids_of_row = [&](int vy, std::size_t* begin, std::size_t* end) {
    const auto y = static_cast<std::size_t>(layout_.real_y(vy));
    *begin = static_cast<std::size_t>(mesh.row_start[y]);
    *end = static_cast<std::size_t>(mesh.row_start[y + 1]);
  };
  const auto empty = [&](std::size_t begin, std::size_t end, std::size_t first_slot, std::size_t step) {
    for (std::size_t id = begin; id < end; ++id)
      for (std::size_t s = first_slot; s < slots; s += step) pred_keys_[id * slots + s] = predecessor_keys::kNone;
  };
  std::size_t b0, e0;
  ids_of_row(vy0, &b0, &e0);
  if (band == 0) {
    empty(b0, e0, 0, 1);
  } else {
    empty(b0, e0, 1, 2);
  }
  const std::size_t band_end = band + 1 < layout_.tiles_y ? static_cast<std::size_t>(band_first_id_[band + 1])
                                                          : mesh.vertices.size();
  std::fill(pred_keys_ + e0 * slots, pred_keys_ + band_end * slots, predecessor_keys::kNone);
  if (band + 1 < layout_.tiles_y) {
    std::size_t b1, e1;
    ids_of_row(vy1, &b1, &e1);
    empty(b1, e1, 0, 2);
  }
}

// The slots empty_band_slots() emptied are the ones the row of tiles wrote:
// the odd ones ("from below") of its own rows, the even ones ("from above")
// of its rows but the first and of the next row of tiles' first row.
void Tritree::band_predecessor_bounds(int band, const Mesh& mesh, Band& b) const {
  int vy0, vy1;
  band_rows(band, &vy0, &vy1);
  const auto row_end = [&](int vy) {
    return mesh.row_start[static_cast<std::size_t>(layout_.real_y(vy)) + 1];
  };
  const auto n = static_cast<std::int32_t>(mesh.vertices.size());
  const bool last = band + 1 == layout_.tiles_y;
  const std::int32_t begin = mesh.row_start[static_cast<std::size_t>(layout_.real_y(vy0))];
  const std::int32_t own_end = last ? n : band_first_id_[band + 1];
  const std::int32_t next_first_end = last ? n : row_end(vy1);
  const std::int32_t first_end = row_end(vy0);
  const auto keys = reinterpret_cast<const std::int32_t*>(pred_keys_);
  // One pass: the first row's odd slots, every slot of the rows between, the
  // next first row's even slots.
  widen_predecessor_bounds(keys, pred_slots_, vertices_, begin, first_end, 1, 2, &b.bounds);
  widen_predecessor_bounds(keys, pred_slots_, vertices_, first_end, own_end, 0, 1, &b.bounds);
  widen_predecessor_bounds(keys, pred_slots_, vertices_, own_end, next_first_end, 0, 2, &b.bounds);
}

void Tritree::begin_mesh(Mesh& mesh) const {
  mesh.width = gray_.width;
  mesh.height = gray_.height;
  mesh.row_start.resize(static_cast<std::size_t>(gray_.height) + 1);  // within capacity
}

void Tritree::finish(Mesh& mesh) {
  const int w = gray_.width, h = gray_.height;
  if (layout_.strip()) {
    // The two triangles of the diagonal: corners (0,0), (W-1,0), (0,H-1), (W-1,H-1).
    begin_mesh(mesh);
    mesh.vertices.clear();
    mesh.vertices.push_back(Vertex{0, 0});
    mesh.vertices.push_back(Vertex{w - 1, 0});
    mesh.vertices.push_back(Vertex{0, h - 1});
    mesh.vertices.push_back(Vertex{w - 1, h - 1});
    for (int y = 0; y <= h; ++y) mesh.row_start[static_cast<std::size_t>(y)] = y == 0 ? 0 : (y < h ? 2 : 4);
    mesh.triangles.resize(2);  // within capacity
    mesh.triangles[0] = Triangle{0, 1, 3};
    mesh.triangles[1] = Triangle{0, 3, 2};
    mesh.criterion_splits = mesh.forced_splits = 0;
    return;
  }
  // The split counts; each row of tiles' leaves are in place, as many as
  // count_vertices() counted (anything else is a broken mesh: stop).
  std::int64_t criterion = 0, forced = 0;
  for (int band = 0; band < layout_.tiles_y; ++band) {
    const Band& b = bands_[band];
    const std::size_t end = band + 1 < layout_.tiles_y ? band_start_[band + 1] : mesh.triangles.size();
    if (b.leaves + b.count != mesh.triangles.data() + end) {
      std::fprintf(stderr, "tristereo: tritree row of tiles %d emitted %zu leaves, Euler's count says %zu\n", band,
                   b.count, end - band_start_[band]);
      std::abort();
    }
    criterion += b.criterion;
    forced += b.forced;
  }
  mesh.criterion_splits = criterion;
  mesh.forced_splits = forced;
}

}  // namespace tristereo
