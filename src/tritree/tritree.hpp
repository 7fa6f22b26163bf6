// The tritree mesher of the integer path (paper section 3.1; docs/model.md
// section 1 is the exact definition, docs/tritree.md explains the layout).
//
//   Tritree tree;
//   tree.configure(640, 480, params);   // reserves everything, throws Error
//   Mesh mesh;
//   tree.reserve(mesh);                 // so build() never grows `mesh`
//   tree.build(gray, mesh, &pool);      // no heap allocation
//
// A right-triangle hierarchy (RTIN) on power-of-two tiles (rtin_layout.hpp).
// build() runs three passes over the image:
//  1. per tile, bottom-up: the pixel moments of every triangle small enough to
//     be tested (sums of its children's), its split test in O(1), and
//     need(m) |= wants | need(children's midpoints) at its hypotenuse midpoint m;
//  2. need carried up across tile borders (a midpoint on a border is shared by
//     two tiles);
//  3. per tile, top-down: a triangle splits when need(its midpoint); the
//     leaves become the canonical mesh (tritree_output.cpp).
// Both triangles of a hypotenuse read the same need, and a parent's need
// includes its children's, which is what keeps the mesh conforming.
#pragma once

#include "tristereo/trace.hpp"

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "src/aggregate/predecessor_offers.hpp"
#include "src/memory/large_array.hpp"
#include "src/tritree/pixel_moments.hpp"
#include "src/tritree/rtin_layout.hpp"
#include "tristereo/image.hpp"
#include "tristereo/mesh.hpp"
#include "tristereo/params.hpp"

namespace tristereo {

class SideWork;
class ThreadPool;
struct KernelSet;

// What the last build() left behind, for the interpolation by midpoints
// (src/interp/interpolate_midpoints.hpp): the hierarchy's layout and the need
// grid. Valid until the next build() or configure().
struct TritreeGrid {
  RtinLayout layout;
  const std::uint8_t* need = nullptr;      // (vw + 1) x (vh + 1), bit 0 = need(m)
  // The leaves with a corner on a moved line (stretched: not the power-of-two
  // triangles of their virtual corners), as vertex ids.
  const Triangle* stretched = nullptr;
  std::size_t stretched_count = 0;
  // Where each row of tiles' leaves begin in Mesh::triangles (layout.tiles_y
  // entries; row ty's run to row ty + 1's start, the last row's to the end).
  const std::size_t* band_start = nullptr;

  // A grid point (virtual coordinates) is a vertex: a tile corner or need(m).
  bool is_vertex(int x, int y) const {
    return (need[static_cast<std::size_t>(y) * (layout.vw + 1) + x] & 1) != 0 ||
           (x % layout.tile == 0 && y % layout.tile == 0);
  }
};

class Tritree {
 public:
  // Reserves storage for images up to max_width x max_height (2 ..
  // kMaxImageSide each); pages are touched only by the frames that use them.
  // Throws Error(kInvalidArgument) naming the bad value (sizes,
  // params.max_area_px2 outside 1..kMaxAreaLimitPx2, psnr_deci_db outside
  // kMinPsnrDeciDb..kMaxPsnrDeciDb, min_area_px2 outside
  // 1..largest_min_area_px2(max_area_px2)); the tree is then unconfigured.
  // `kernels` (null: the set KernelChoice::kAuto resolves to) runs the
  // side-4 level of plain tiles when it applies (A_min >= 2, A_max >= 8).
  void configure(int max_width, int max_height, const TritreeParams& params, const KernelSet* kernels = nullptr);
  bool configured() const { return max_width_ > 0; }

  // Reserves capacity in `mesh` so build() never allocates into it.
  // Throws Error(kNotConfigured) before configure().
  void reserve(Mesh& mesh) const;

  // Bytes of the tree's own buffers (allocated capacities; src/tritree/tritree_memory.cpp).
  std::size_t working_memory_bytes() const;

  // Builds the mesh of `gray` (1 channel, 2 .. max size, stride >= width).
  // Throws Error on bad input, leaving `mesh` untouched. No heap allocation
  // once `mesh` has been reserve()d. With a started `pool` (called from its
  // owner thread), pass 1 runs on its workers, one row of tiles each at a time
  // (even rows, then odd ones: rows that run together share no grid point);
  // the mesh is identical for every pool size.
  // With `preds` (slots for every vertex the mesh may have), the build also
  // writes each vertex's path predecessors (src/aggregate/predecessor_offers.hpp)
  // as it emits the leaves, and sets preds->filled and preds->reach; a
  // 2-pixel strip leaves filled false.
  // With `side`, the pool's other workers take its chunks while the build
  // runs a serial step (platform/side_work.hpp).
  void build(ImageView<const std::uint8_t> gray, Mesh& mesh, ThreadPool* pool = nullptr,
             PredecessorTable* preds = nullptr, SideWork* side = nullptr);
  // Pass 1 runs on at most this many pool workers (each has its tile scratch).
  static constexpr int kMaxTileWorkers = 8;

  // Wall time of the last build's parts (monotonic clock), for benchmarks.
  struct BuildTimes {
    std::int64_t criterion_ns = 0;  // passes 1 and 2
    std::int64_t output_ns = 0;     // pass 3 and the canonical mesh
  };
  const BuildTimes& build_times() const { return times_; }
  int tile_side() const { return tile_; }
  // The last build's grid (see TritreeGrid); need is null for a 2-pixel strip.
  TritreeGrid grid() const;

  // Rows of tiles go to `trace` as work items (null = none; not owned).
  void set_trace(FrameTrace* trace) { trace_ = trace; }

 private:
  FrameTrace* trace_ = nullptr;
  // A triangle of the hierarchy: a half of the square of side s at (x0, y0)
  // (virtual coordinates; part 0 = the half along the top side, 1 = the
  // other), or the side triangle from the square's centre to side `part`
  // (0 top, 1 right, 2 bottom, 3 left).
  struct Tri {
    bool half;
    int s, x0, y0, part;
  };
  enum class Where { kInside, kCrossing, kOutside };
  // The owned-pixel spans of the general tiles' stretched and border
  // triangles (moments_by_spans), kept per kind of tile: the last column's
  // (but the last row's) and the last row's (but the last column's), each by
  // its tile's diagonal. Tiles of a kind are translates of one another and
  // the fill rule's ties on the image's last row and column fall alike in
  // each, so a worker's first tile of a kind records its triangles' spans
  // and geometric sums in call order, and its next ones, in this frame and
  // the following ones of that size, replay them: every call checks its
  // corners against the record, and anything else computes afresh
  // (tritree_spans.cpp).
  struct SpanRecord {
    std::uint64_t key_xy;                   // the corners relative to the tile origin, 16 bits each:
    std::uint32_t key_y;                    // x0 x1 x2 y0 | y1 y2 (two words: no byte compare)
    std::uint16_t first, count;             // its rows in SpanKind::rows
    std::int32_t n, sx, sy, sxx, sxy, syy;  // geometric sums, relative to the tile origin
  };
  struct SpanRow {
    std::int16_t dy, x0, x1;  // row ty0 + dy, pixels tx0 + [x0, x1)
  };
  struct SpanKind {
    SpanRecord* records = nullptr;
    SpanRow* rows = nullptr;
    std::uint32_t n_records = 0, n_rows = 0;
    bool recorded = false, unusable = false;
  };
  struct alignas(8) SpanCache {
    std::array<SpanKind, 4> kinds{};
    int width = 0, height = 0;    // the image size the records hold for
    SpanKind* current = nullptr;  // the tile being built's kind, or null
    std::uint32_t cursor = 0;     // its next call
    bool recording = false;
  };
  // Pass 1's per-tile moments (see the members below).
  struct TileScratch {
    std::array<PixelMoments*, 6> half{};  // S <= 64: sides 2 .. 64
    PixelMoments* side = nullptr;
    std::array<IntensityMoments*, 6> half_i{};  // plain tiles (tile_plain)
    IntensityMoments* side_i = nullptr;
    // The side-4 level of a row of tiles' plain tiles (side4_band), per row
    // of squares: wants bits, then the halves' sums (KernelSet::side4_tests_u8).
    std::uint32_t* side4_wants = nullptr;
    std::int32_t* side4_sums = nullptr;
    // The side-8 level's, likewise (side8_band, KernelSet::side8_tests_s32).
    std::uint32_t* side8_wants = nullptr;
    std::int32_t* side8_sums = nullptr;
    SpanCache* spans = nullptr;  // the general tiles' (this worker slot's)
    // Pass 3: the vertex ids of the row of tiles this worker slot emits,
    // (S + 2) x max width (Band::ids).
    std::int32_t* band_ids = nullptr;
  };

  void validate_image(ImageView<const std::uint8_t> gray) const;
  void general_square(int tx0, int ty0, int x0, int y0, int s, const TileScratch& sc, PixelMoments* out);
  void carry_inside_tile(int tx0, int ty0);
  template <class ChildrenSums>
  bool general_wants(const int* vx, const int* vy, bool moments_needed, int tx0, int ty0, const TileScratch& sc,
                     PixelMoments& m, ChildrenSums children) const;
  void begin_span_tile(const TileScratch& sc, int tx, int ty) const;
  static void end_span_tile(const TileScratch& sc);
  PixelMoments tile_moments_by_spans(const int* rx, const int* ry, int ox, int oy, const TileScratch& sc) const;
  static PixelMoments full_moments(const IntensityMoments& mi, const ShapeMoments& g, int ox, int oy, int ax,
                                   int ay);
  template <int S>
  void tile_plain(int tx0, int ty0, const TileScratch& sc, bool side4_ready);
  void side4_band(int ty0, int plain_tiles, const TileScratch& sc) const;
  void side8_band(int ty0, int plain_tiles, const TileScratch& sc) const;
  template <int S, int s>
  void apply_kernel_level(int tx0, int ty0, const std::uint32_t* wants_rows, const std::int32_t* sums_rows,
                          std::size_t ss, IntensityMoments* halves);
  template <int S>
  void side2_sums_only(int tx0, int ty0, const TileScratch& sc) const;
  template <int S, int s>
  void plain_level(int tx0, int ty0, const TileScratch& sc);
  void tile_plain_of_side(int side, int tx0, int ty0, const TileScratch& sc, bool side4_ready = false);
  void carry_across_tile_borders(int ty0, int ty1);
  void carry_up(int x, int y);
  // Pass 3 writes each row of tiles' leaves straight into its place in the
  // mesh (counted beforehand by count_vertices(), so rows of tiles can run
  // on different workers), with its own split counts, and its stretched
  // leaves into its region of stretched_ (stretched_per_band_ each, the last
  // row of tiles 8 W more).
  struct Band {
    Triangle* leaves = nullptr;
    std::size_t count = 0;
    std::int64_t criterion = 0, forced = 0;
    Triangle* stretched = nullptr;
    std::int64_t stretched_count = 0;
    // Its vertex ids at their real pixels (valid at the vertices only): real
    // row ids_y0 + r at ids[r * width], rows real_y(its first) .. real_y(the
    // next one's first, or vh), at most S + 2 (a pass-3 worker's).
    std::int32_t* ids = nullptr;
    std::int64_t ids_y0 = 0;
    // The extent of the predecessors its leaves offered (preds only).
    PredecessorBounds bounds;
  };
  void collect_stretched();
  void emit_tile(Band& b, int tx0, int ty0, bool plain);
  void emit(Band& b, int ax, int ay, int bx, int by, int cx, int cy);
  template <int kSlots>
  void emit_general_rtin(Band& b, int ax, int ay, int bx, int by, int cx, int cy);
  void emit_leaf(Band& b, int ax, int ay, int bx, int by, int cx, int cy);
  void offer_stretched(const Band& b) const;
  template <int kSlots>
  void emit_plain_tile(Band& b, int tx0, int ty0);
  void finish_predecessors(const Mesh& mesh, PredecessorTable* preds) const;
  void begin_mesh(Mesh& mesh) const;
  void finish(Mesh& mesh);
  // The vertices: the counts, first ids and leaf counts of every row of
  // tiles (returns the leaves), then, in pass 3, each one's vertices, row
  // starts (the last one's: to the end) and ids (into `ids`, for b).
  std::size_t count_vertices(Mesh& mesh, ThreadPool* pool);
  void number_band(int band, Mesh& mesh, std::int32_t* ids, Band& b) const;
  void next_first_row_ids(int band, const Mesh& mesh, Band& b) const;
  std::uint64_t vertex_bits(int vy, int vx0) const;
  void band_rows(int band, int* vy0, int* vy1) const;
  // Empties the predecessor slots that row of tiles `band`'s leaves offer to,
  // right before it emits them (so they are in cache when offered).
  void empty_band_slots(int band, const Mesh& mesh) const;
  // Once it emitted them: the extent of the predecessors in those slots,
  // into b.bounds (still in cache; the path matcher's scan of the whole
  // table, on one worker, is then not needed).
  void band_predecessor_bounds(int band, const Mesh& mesh, Band& b) const;

  // Geometry of the hierarchy (virtual coordinates).
  void corners(const Tri& t, int* x, int* y) const;
  Where where(const int* x, const int* y) const;
  static void midpoint(const Tri& t, int* mx, int* my);
  bool parent(const Tri& t, Tri* p) const;
  int need_bit(const Tri& t) const;  // which wants bit of its midpoint's cell is t's
  int find_tris(int mx, int my, Tri* out) const;
  std::uint8_t& cell(int x, int y) { return need_[static_cast<std::size_t>(y) * (layout_.vw + 1) + x]; }
  // Sums of the real triangle's owned pixels, relative to (ox, oy), by spans.
  PixelMoments moments_by_spans(const int* rx, const int* ry, int ox, int oy) const;
  bool wants_split(const int* rx, const int* ry, const PixelMoments* m, int ox, int oy) const;

  int max_width_ = 0;
  int max_height_ = 0;
  TritreeParams params_;
  std::uint64_t mse_q8_ = 0;
  int tile_ = 2;
  // Shapes of plain tiles' triangles per level (side 2 << l): side triangles
  // 0..3 (top, right, bottom, left), halves 0..3 ('\\' upper right, lower
  // left, '/' upper left, lower right), first corner as corners() lists it.
  std::array<std::array<ShapeMoments, 4>, 6> side_shape_{}, half_shape_{};
  // The side-4 level by KernelSet::side4_tests_u8 (when the squares of side
  // 2 are not tested and those of side 4 are): its SSE limits (side4_shapes.hpp)
  // and the squares per row of its band buffers.
  const KernelSet* kernels_ = nullptr;
  bool side4_kernel_ = false;
  std::array<std::int32_t, 8> side4_limit_{};
  std::size_t side4_stride_ = 0;
  // The side-8 level by KernelSet::side8_tests_s32 (from the side-4 kernel's
  // sums; when both levels' triangles are all tested: A_max >= 32).
  bool side8_kernel_ = false;
  std::array<std::int64_t, 8> side8_limit_{};
  std::size_t side8_stride_ = 0;

  // Per-build state.
  ImageView<const std::uint8_t> gray_;
  RtinLayout layout_;
  BuildTimes times_;
  std::int64_t criterion_splits_ = 0, forced_splits_ = 0;

  // Everything below points into arena_, one block reserved by configure():
  // need_: one byte per virtual grid point: bit 0 need(m), bits 1 and 2
  // wants of the (up to) two triangles whose hypotenuse midpoint it is.
  LargeArray<std::uint64_t> arena_;
  std::size_t arena_bytes_ = 0;
  std::uint8_t* need_ = nullptr;
  // Per-tile scratch of pass 1: moments of the square halves of each level
  // (level l: side 2^(l+1)), and of one level's side triangles.
  // (one per pass-1 worker, at most kMaxTileWorkers).
  std::array<TileScratch, kMaxTileWorkers> scratch_{};
  std::size_t span_records_ = 0, span_rows_ = 0;  // capacity of each SpanKind
  // Pass 1 on a pool: each row of tiles marks itself done, so a row of the
  // second parity starts as soon as its two neighbours are (configure()).
  std::unique_ptr<std::atomic<std::uint8_t>[]> row_done_;
  // Pass 3: the leaves as rotated triangles.
  Band* bands_ = nullptr;                 // one per row of tiles
  std::size_t* band_start_ = nullptr;     // each row of tiles' leaf count, then where they go in the mesh
  std::int32_t* band_first_id_ = nullptr; // vertex numbering: each row of tiles' count, then first id
  Triangle* stretched_ = nullptr;         // stretched leaves (TritreeGrid::stretched)
  std::size_t stretched_count_ = 0;
  // A row of tiles' stretched leaves touch its last column's moved line (the
  // last row's, its moved row too), at most 8 at each of its vertices there.
  std::size_t stretched_per_band_ = 0;
  // The build's predecessor output (PredecessorTable), keys until finished.
  std::uint32_t* pred_keys_ = nullptr;
  int pred_slots_ = 0;  // 0 (none), 2 or 6 per vertex
  const Vertex* vertices_ = nullptr;  // the mesh's, once numbered
};

}  // namespace tristereo
