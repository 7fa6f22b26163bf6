// Tritree configuration: parameter validation and the one-time allocation of
// every buffer a build can need.
#include <algorithm>
#include <climits>
#include <cstdint>
#include <memory>
#include <new>
#include <string>

#include "src/kernels/dispatch.hpp"
#include "src/kernels/kernel_set.hpp"
#include "src/model/psnr_threshold.hpp"
#include "src/tritree/fill_rule.hpp"
#include "src/tritree/tritree.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

namespace {

void check_range(const char* what, long long value, long long lo, long long hi) {
  if (value < lo || value > hi) {
    throw Error(ErrorCode::kInvalidArgument,
                std::string("tritree: ") + what + " = " + std::to_string(value) +
                    " is outside " + std::to_string(lo) + ".." + std::to_string(hi));
  }
}

// Every leaf has area >= 1 px^2 (its area is at least its virtual area) and
// the leaves tile the (W-1) x (H-1) rectangle; an image with a side of 2
// pixels has its two triangles.
std::size_t max_leaves(int w, int h) {
  const std::size_t cells = static_cast<std::size_t>(w - 1) * static_cast<std::size_t>(h - 1);
  return cells < 2 ? 2 : cells;
}

// A stretched leaf has a corner on the moved last column or row, and a vertex
// has at most 8 leaves around it.
// Uninitialised storage (src/memory/large_array.hpp): a frame smaller than the
// configured maximum never faults the rest in.
// PixelMoments has default member initialisers, so the block is raw words.
template <class T>
LargeArray<T> reserve_array(std::size_t n) {
  return large_array<T>(n);
}

// The geometric sums of a triangle's owned pixels relative to its first corner,
// far from the image's last row and column.
ShapeMoments shape_moments(const int* x, const int* y) {
  ShapeMoments g;
  g.ux = x[1] - x[0], g.uy = y[1] - y[0], g.vx = x[2] - x[0], g.vy = y[2] - y[0];
  g.area2 = g.ux * g.vy - g.uy * g.vx;
  const Vertex a{x[0], y[0]}, b{x[1], y[1]}, c{x[2], y[2]};
  const int far = 1 << 20;
  for (int py = std::min({y[0], y[1], y[2]}); py <= std::max({y[0], y[1], y[2]}); ++py)
    for (int px = std::min({x[0], x[1], x[2]}); px <= std::max({x[0], x[1], x[2]}); ++px) {
      if (!owns_pixel(a, b, c, px, py, far, far)) continue;
      const int dx = px - x[0], dy = py - y[0];
      g.n += 1, g.sx += dx, g.sy += dy, g.sxx += dx * dx, g.sxy += dx * dy, g.syy += dy * dy;
    }
  return g;
}

}  // namespace

void Tritree::configure(int max_width, int max_height, const TritreeParams& params, const KernelSet* kernels) {
  max_width_ = 0;  // unconfigured until everything below succeeded
  check_range("max_width", max_width, 2, kMaxImageSide);
  check_range("max_height", max_height, 2, kMaxImageSide);
  check_range("max_area_px2", params.max_area_px2, 1, kMaxAreaLimitPx2);
  check_range("psnr_deci_db", params.psnr_deci_db, kMinPsnrDeciDb, kMaxPsnrDeciDb);
  check_range("min_area_px2", params.min_area_px2, 1, largest_min_area_px2(params.max_area_px2));

  const std::size_t pixels = static_cast<std::size_t>(max_width) * max_height;
  tile_ = tile_side_for(params.max_area_px2);
  // One block, carved in order of alignment: the moments of one tile per
  // pass-1 worker (level l holds the halves of the squares of side 2^(l+1),
  // then one level's side triangles, pass 3's ids of a row of tiles), the
  // row-of-tiles starts, the stretched leaves, the rows of tiles' first ids,
  // the need grid (the
  // virtual grid has at most W x H points).
  std::size_t moments = static_cast<std::size_t>(tile_ / 4 + 1) * (tile_ / 4 + 1) * 4;
  for (int s = 2; s <= tile_; s *= 2) moments += static_cast<std::size_t>(tile_ / s) * (tile_ / s) * 2;
  // The plain tiles' intensity moments, in the same layout (16 bytes each).
  const std::size_t intensity_moments = moments;
  const std::size_t bands = static_cast<std::size_t>(max_height) / 2 + 2;
  // Pass 3 writes the leaves straight into the mesh (each row of tiles'
  // count is known beforehand, tritree_output.cpp).
  const RtinLayout largest(max_width, max_height, params.max_area_px2);
  // Each row of tiles' region of stretched leaves: 8 at each vertex on a
  // moved line, at most S + 2 of them on the last column's (its rows and the
  // next one's first, the moved last row below the last row of tiles' own),
  // and W more on the last row's.
  stretched_per_band_ = 8 * static_cast<std::size_t>(tile_ + 2);
  const std::size_t stretched = static_cast<std::size_t>(largest.tiles_y) * stretched_per_band_ + 8 * static_cast<std::size_t>(max_width);
  // The side-4 level by the kernel when the 2 x 2 squares' halves are not
  // tested (A_min >= 2) and the 4 x 4 squares' triangles all are (A_max >= 8):
  // per pass-1 worker, a row of tiles' results, S / 4 rows of squares.
  kernels_ = kernels != nullptr ? kernels : &kernel_set_for(KernelChoice::kAuto);
  side4_kernel_ = params.min_area_px2 > 1 && 2 * params.max_area_px2 >= 16;
  side4_stride_ = side4_kernel_ ? static_cast<std::size_t>(largest.tiles_x) * (tile_ / 4) : 0;
  const std::size_t side4_words = (static_cast<std::size_t>(tile_ / 4) * side4_stride_ * 9 + 1) / 2 * 2;  // 8-byte multiple
  // The side-8 level by its kernel, from the side-4 kernel's sums, when the
  // halves of the 8 x 8 squares are tested too (A_max >= 32, so S >= 16).
  side8_kernel_ = side4_kernel_ && 2 * params.max_area_px2 >= 64;
  side8_stride_ = side8_kernel_ ? static_cast<std::size_t>(largest.tiles_x) * (tile_ / 8) : 0;
  const std::size_t side8_words = (static_cast<std::size_t>(tile_ / 8) * side8_stride_ * 9 + 1) / 2 * 2;
  // The general tiles' span records (SpanCache): per kind, at most six
  // triangles of each square on the tile's last column (row) of squares of
  // every side s, of at most s + 2 rows each.
  span_records_ = 0;
  span_rows_ = 0;
  for (int s = 2; s <= tile_; s *= 2) {
    span_records_ += static_cast<std::size_t>(6 * (tile_ / s));
    span_rows_ += static_cast<std::size_t>(6 * (tile_ / s) * (s + 2));
  }
  span_rows_ = (span_rows_ + 3) / 4 * 4;  // 6-byte rows: an 8-byte multiple
  // Pass 3's ids of one row of tiles per worker (Band::ids): S + 2 rows.
  const std::size_t ids_words = (static_cast<std::size_t>(tile_ + 2) * max_width + 1) / 2 * 2;  // 8-byte multiple
  static_assert(sizeof(SpanRecord) % 8 == 0 && sizeof(SpanCache) % 8 == 0, "the carving stays 8-byte aligned");
  const std::size_t span_bytes = sizeof(SpanCache) + 4 * (span_records_ * sizeof(SpanRecord) + span_rows_ * sizeof(SpanRow));
  const std::size_t bytes = kMaxTileWorkers * (span_bytes + moments * sizeof(PixelMoments) +
                                                 intensity_moments * sizeof(IntensityMoments) +
                                                 (side4_words + side8_words) * sizeof(std::int32_t) +
                                                 ids_words * sizeof(std::int32_t)) +
                            stretched * sizeof(Triangle) + bands * sizeof(Band) +
                            bands * sizeof(std::size_t) + (bands + 1) * sizeof(std::int32_t) + pixels;
  arena_ = reserve_array<std::uint64_t>((bytes + 7) / 8);
  arena_bytes_ = (bytes + 7) / 8 * 8;
  char* next = reinterpret_cast<char*>(arena_.get());
  const auto take = [&next](std::size_t n) {
    char* p = next;
    next += n;
    return p;
  };
  for (TileScratch& sc : scratch_) {
    sc.spans = new (take(sizeof(SpanCache))) SpanCache{};
    for (SpanKind& k : sc.spans->kinds) {
      k.records = reinterpret_cast<SpanRecord*>(take(span_records_ * sizeof(SpanRecord)));
      k.rows = reinterpret_cast<SpanRow*>(take(span_rows_ * sizeof(SpanRow)));
    }
    PixelMoments* m = reinterpret_cast<PixelMoments*>(take(moments * sizeof(PixelMoments)));
    std::size_t level = 0;
    for (int s = 2; s <= tile_; s *= 2) {
      sc.half[level++] = m;
      m += static_cast<std::size_t>(tile_ / s) * (tile_ / s) * 2;
    }
    sc.side = m;
    IntensityMoments* mi = reinterpret_cast<IntensityMoments*>(take(intensity_moments * sizeof(IntensityMoments)));
    level = 0;
    for (int s = 2; s <= tile_; s *= 2) {
      sc.half_i[level++] = mi;
      mi += static_cast<std::size_t>(tile_ / s) * (tile_ / s) * 2;
    }
    sc.side_i = mi;
    char* side4 = take(side4_words * sizeof(std::int32_t));
    sc.side4_wants = side4_kernel_ ? reinterpret_cast<std::uint32_t*>(side4) : nullptr;
    sc.side4_sums = side4_kernel_ ? reinterpret_cast<std::int32_t*>(side4) + static_cast<std::size_t>(tile_ / 4) * side4_stride_
                                  : nullptr;
    sc.band_ids = reinterpret_cast<std::int32_t*>(take(ids_words * sizeof(std::int32_t)));
    char* side8 = take(side8_words * sizeof(std::int32_t));
    sc.side8_wants = side8_kernel_ ? reinterpret_cast<std::uint32_t*>(side8) : nullptr;
    sc.side8_sums = side8_kernel_ ? reinterpret_cast<std::int32_t*>(side8) + static_cast<std::size_t>(tile_ / 8) * side8_stride_
                                  : nullptr;
  }
  // Shape moments by the fill rule itself, on a square far from any border,
  // each with its threshold (the model's right-hand side, mse_q8 n area2^2).
  const std::uint64_t mse_q8 = mse_threshold_q8(params.psnr_deci_db);
  const auto with_limit = [mse_q8](ShapeMoments g) {
    const auto a2 = static_cast<std::uint64_t>(g.area2);
    g.fail_above_q8 = mse_q8 * static_cast<std::uint64_t>(g.n) * a2 * a2;
    return g;
  };
  for (int l = 0; (2 << l) <= tile_; ++l) {
    const int s = 2 << l, o = 2 * kMaxAreaLimitPx2;
    for (int k = 0; k < 4; ++k) {
      int x[3], y[3];
      corners(Tri{false, s, o, o, k}, x, y);
      side_shape_[static_cast<std::size_t>(l)][static_cast<std::size_t>(k)] = with_limit(shape_moments(x, y));
    }
    for (int k = 0; k < 4; ++k) {
      // '\\' squares have X0/s + Y0/s even: (o, o) with o/s even, '/' ones (o + s, o).
      int x[3], y[3];
      corners(Tri{true, s, k < 2 ? o : o + s, o, k & 1}, x, y);
      half_shape_[static_cast<std::size_t>(l)][static_cast<std::size_t>(k)] = with_limit(shape_moments(x, y));
    }
  }
  // The kernel's limits: SSE * 256 > fail_above_q8 is SSE > fail_above_q8 / 256
  // (rounded down) for an integer SSE; a triangle below twice the minimum
  // area never wants (INT32_MAX, above every SSE of side 4).
  const auto side4_limit = [](const ShapeMoments& g, bool may_want) {
    const std::uint64_t l = g.fail_above_q8 / 256;
    return may_want && l < static_cast<std::uint64_t>(INT32_MAX) ? static_cast<std::int32_t>(l) : INT32_MAX;
  };
  if (side8_kernel_) {  // as side 4's, in int64 (SSE < 2^37); INT64_MAX: never
    const bool sides_may_want = 32 >= 4 * params.min_area_px2, halves_may_want = 64 >= 4 * params.min_area_px2;
    const auto limit = [](const ShapeMoments& g, bool may_want) {
      return may_want ? static_cast<std::int64_t>(g.fail_above_q8 / 256) : INT64_MAX;
    };
    for (std::size_t k = 0; k < 4; ++k) {
      side8_limit_[k] = limit(side_shape_[2][k], sides_may_want);
      side8_limit_[4 + k] = limit(half_shape_[2][k], halves_may_want);
    }
  }
  if (side4_kernel_) {
    const bool sides_may_want = 8 >= 4 * params.min_area_px2, halves_may_want = 16 >= 4 * params.min_area_px2;
    for (std::size_t k = 0; k < 4; ++k) {
      side4_limit_[k] = side4_limit(side_shape_[1][k], sides_may_want);
      side4_limit_[4 + k] = side4_limit(half_shape_[1][k], halves_may_want);
    }
  }
  // The 8-byte row-of-tiles starts before the 12-byte triangles: after an odd
  // number of triangles they were misaligned (UBSan, found by fuzz_pipeline).
  // The rows of tiles' pass-3 state (int64 counts) right after the moments,
  // while the carving is 8-byte aligned; the size_t starts are 4 bytes each on
  // 32-bit targets.
  static_assert(sizeof(Band) % 8 == 0 && alignof(Band) <= 8, "Band keeps the carving 8-byte aligned");
  bands_ = reinterpret_cast<Band*>(take(bands * sizeof(Band)));
  row_done_ = std::make_unique<std::atomic<std::uint8_t>[]>(bands);
  band_start_ = reinterpret_cast<std::size_t*>(take(bands * sizeof(std::size_t)));
  stretched_ = reinterpret_cast<Triangle*>(take(stretched * sizeof(Triangle)));
  band_first_id_ = reinterpret_cast<std::int32_t*>(take((bands + 1) * sizeof(std::int32_t)));
  need_ = reinterpret_cast<std::uint8_t*>(take(pixels));

  params_ = params;
  mse_q8_ = mse_q8;
  max_height_ = max_height;
  max_width_ = max_width;
}

void Tritree::reserve(Mesh& mesh) const {
  if (!configured()) throw Error(ErrorCode::kNotConfigured, "tritree: reserve() before configure()");
  mesh.vertices.reserve(static_cast<std::size_t>(max_width_) * max_height_);
  mesh.triangles.reserve(max_leaves(max_width_, max_height_));
  mesh.row_start.reserve(static_cast<std::size_t>(max_height_) + 1);
}

void Tritree::validate_image(ImageView<const std::uint8_t> gray) const {
  if (!configured()) throw Error(ErrorCode::kNotConfigured, "tritree: build() before configure()");
  if (gray.data == nullptr) throw Error(ErrorCode::kInvalidArgument, "tritree: image data is null");
  if (gray.channels != 1) {
    throw Error(ErrorCode::kUnsupportedFormat,
                "tritree: image has " + std::to_string(gray.channels) +
                    " channels, expected 1 (gray)");
  }
  check_range("image width", gray.width, 2, max_width_);
  check_range("image height", gray.height, 2, max_height_);
  if (gray.stride_bytes < gray.width) {
    throw Error(ErrorCode::kInvalidArgument,
                "tritree: stride_bytes = " + std::to_string(gray.stride_bytes) +
                    " is smaller than the width " + std::to_string(gray.width));
  }
}

}  // namespace tristereo
