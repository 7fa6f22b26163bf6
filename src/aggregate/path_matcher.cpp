#include "src/aggregate/path_matcher.hpp"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <string>
#include <thread>

#include "platform/clock.hpp"
#include "platform/cpu_relax.hpp"
#include "platform/prefetch.hpp"
#include "src/cost/byte_means.hpp"
#include "src/dp/penalty.hpp"
#include "src/memory/capacity_bytes.hpp"
#include "src/tritree/rtin_layout.hpp"
#include "src/dp/subpixel.hpp"
#include "src/select/confidence.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

namespace {
constexpr std::size_t kLanesRound = 16;  // rows start on 32-byte boundaries
constexpr std::uint16_t kGuard = 0xFFFF;
// How far ahead run_tile prefetches a sample's costs and sums (2 to 16
// measured the same).
constexpr int kPrefetchSamples = 4;

std::size_t round_up(std::size_t v) { return (v + kLanesRound - 1) / kLanesRound * kLanesRound; }
// Census costs by rows: windows of at most this many pixels may be summed
// per sample without column sums (census_costs_by_rows).
constexpr int kMaxDirectCells = 25;

// Bands a pass may have under way with `workers` workers. The two passes run
// at once, so each has about half of the workers, each on a tile of its own
// band; two more keep a worker from waiting at a band's end. The rings hold
// the rows of these bands (plan_pass): with N + 1 of them, a one-worker trace
// cut for 16 workers spent 13.1-13.5 ms in the path tiles of the synthetic
// D = 128 frame, with one 10.3 (7.3 uncut), and the scaling model's schedule
// loses under 2 % at 16 workers with N / 2 + 2.
int bands_in_flight(int workers) { return workers <= 2 ? 1 : workers / 2 + 2; }

// Storage that is not touched until a frame writes it (src/memory/large_array.hpp).
template <class T>
LargeArray<T> untouched(std::size_t n) {
  return large_array<T>(n);
}
}  // namespace

void PathMatcher::configure(int max_width, int max_height, const StereoParams& params,
                            const KernelSet& kernels, int workers, int schedule_workers) {
  if (max_width < 2 || max_width > kMaxImageSide || max_height < 2 || max_height > kMaxImageSide)
    throw Error(ErrorCode::kInvalidArgument, "path matcher: maximum size " +
                                                 std::to_string(max_width) + "x" +
                                                 std::to_string(max_height) + " is outside 2.." +
                                                 std::to_string(kMaxImageSide));
  if (workers < 1 || workers > 256)
    throw Error(ErrorCode::kInvalidArgument, "path matcher: workers = " + std::to_string(workers));
  if (schedule_workers < 0 || schedule_workers > 256)
    throw Error(ErrorCode::kInvalidArgument, "path matcher: schedule workers = " + std::to_string(schedule_workers));
  validate_params(params);
  if (!kernels.path_steps_u16 || !kernels.path_steps_u8 || !kernels.winner_u16 || !kernels.sum_rows_u16 || !kernels.sum_rows_u8 ||
      !kernels.normalize_costs_u8)
    throw Error(ErrorCode::kInvalidArgument, "kernel set '" + std::string(kernels.name) + "' is incomplete");
  const int d = params.num_disp;
  const std::size_t n = static_cast<std::size_t>(max_width) * static_cast<std::size_t>(max_height);
  params_ = params;
  kernels_ = &kernels;
  max_samples_ = static_cast<int>(n);
  num_disp_ = d;
  directions_ = params.paths.directions;
  cost_stride_ = round_up(static_cast<std::size_t>(d));
  path_stride_ = round_up(static_cast<std::size_t>(d) + 2);
  const int max_gap = std::max(max_width, max_height);
  fill_penalty_table(params.paths.p1_q4, params.paths.gap, max_gap, p1_by_gap_);
  fill_penalty_table(params.paths.p2_q4, params.paths.gap, max_gap, p2_by_gap_);
  penalties_by_gap_ = false;
  // Index 0 is no gap (unused): compare the gaps 2.. with gap 1.
  for (std::size_t g = 2; g < p1_by_gap_.size(); ++g)
    if (p1_by_gap_[g] != p1_by_gap_[1] || p2_by_gap_[g] != p2_by_gap_[1]) penalties_by_gap_ = true;
  if (!penalties_by_gap_) {
    const std::uint32_t a = p1_by_gap_[1], b = std::max(a, p2_by_gap_[1]);
    const auto scale = static_cast<std::uint32_t>(params.paths.p2_edge_scale);
    for (std::uint32_t di = 0; di < 256; ++di)
      p2_by_diff_[di] = static_cast<std::uint16_t>(scale > 0 ? a + (b - a) * scale / (scale + di) : b);
  }
  max_width_ = max_width;
  const bool by_rows = params.cost.kind == CostKind::kCensus;
  const int census_bits = params.cost.census_w * params.cost.census_h - 1;
  byte_costs_ = by_rows && census_bits * params.cost.window_w * params.cost.window_h <= 255;
  ring_len_ = by_rows ? static_cast<std::size_t>(params.cost.window_h) * static_cast<std::size_t>(max_width) * cost_stride_ : 0;
  // Byte rows take half the u16 elements.
  const auto cost_elems = [this](std::size_t n) { return byte_costs_ ? (n + 1) / 2 : n; };
  // C in bytes: the census box sums themselves, when every box a sample can
  // have (clipped at the borders) has a 15-bit reciprocal that gives the
  // model's means (byte_means.hpp); the path kernels take the means in
  // registers. Half the bytes of Q4 costs to write, and to read in both passes.
  const int box_w = params.cost.window_w, box_h = params.cost.window_h;
  inv_pixels_q15_.assign(byte_costs_ ? static_cast<std::size_t>(box_w * box_h) + 1 : 0, 0);
  c_sums_u8_ = byte_costs_;
  for (int a = 1; c_sums_u8_ && a <= box_w; ++a)
    for (int b = 1; c_sums_u8_ && b <= box_h; ++b) {
      const std::uint16_t inv = byte_mean_inv_q15(a * b, census_bits * a * b);
      inv_pixels_q15_[static_cast<std::size_t>(a * b)] = inv;
      c_sums_u8_ = inv != 0;
    }
  costs_len_ = c_sums_u8_ ? (n * cost_stride_ + 1) / 2 : n * cost_stride_;
  preds_len_ = n * static_cast<std::size_t>(directions_ - 2);
  costs_ = untouched<std::uint16_t>(costs_len_);
  preds_ = untouched<std::int32_t>(preds_len_);
  zero_path_.assign(path_stride_, 0);
  zero_path_[0] = kGuard;
  zero_path_[static_cast<std::size_t>(d) + 1] = kGuard;
  // The rings hold the rows of the bands under way plus the rows their
  // predecessors reach up (plan_pass): mesh edges span at most a tile side + 1
  // rows (a leaf's edges span at most a tile side, plus the stretch).
  schedule_workers_ = schedule_workers > 0 ? schedule_workers : workers;
  max_rows_per_band_ = schedule_workers_ <= 2 ? 1 : kMaxRowsPerBand;
  max_in_flight_ = bands_in_flight(schedule_workers_);
  const std::size_t ring_rows = static_cast<std::size_t>(max_in_flight_ + 1) * static_cast<std::size_t>(max_rows_per_band_) +
                                static_cast<std::size_t>(tile_side_for(params.tritree.max_area_px2) + 2);
  const std::size_t ring = std::min(n, ring_rows * static_cast<std::size_t>(max_width) + 1);
  ring_capacity_ = static_cast<int>(ring);
  const std::size_t carries = static_cast<std::size_t>(max_in_flight_) * static_cast<std::size_t>(max_rows_per_band_);
  for (int pass = 0; pass < 2; ++pass) {
    path_rings_[pass].clear();
    path_mins_[pass].clear();
    for (int j = 0; j < directions_ / 2 - 1; ++j) {
      path_rings_[pass].push_back(untouched<std::uint16_t>(ring * path_stride_ + 64));
      path_mins_[pass].push_back(untouched<std::uint16_t>(ring));
    }
    carry_[pass].assign(carries, RowCarry{});
    carry_paths_[pass].assign(carries * path_stride_ + 64, 0);
    for (std::size_t c = 0; c < carries; ++c) {
      carry_paths_[pass][c * path_stride_] = kGuard;
      carry_paths_[pass][c * path_stride_ + static_cast<std::size_t>(d) + 1] = kGuard;
    }
    wavefront_[pass].configure(max_height);
  }
  band_first_.reset(new std::atomic<int>[static_cast<std::size_t>(max_height)]);
  sum_ = untouched<std::uint16_t>(n * cost_stride_);
  workers_.clear();
  workers_.resize(static_cast<std::size_t>(workers));
  for (Worker& w : workers_) {
    w.row_path = std::unique_ptr<std::uint16_t[]>(new std::uint16_t[2 * path_stride_ + 64]());
    w.scratch.resize(d);
    w.total.assign(cost_stride_ + 64, 0);
    if (by_rows) {
      w.pixel_rows = untouched<std::uint16_t>(cost_elems(ring_len_));
      w.column_sums = untouched<std::uint16_t>(cost_elems(static_cast<std::size_t>(max_width) * cost_stride_));
      w.slot_row.assign(static_cast<std::size_t>(params.cost.window_h), -1);
    }
    if (params.validity.lr_max_diff_q4 >= 0 && params.validity.lr_source == LrSource::kSummedCosts) {
      // A row's right pixels xr = x - d_min - k, indexed W - 1 - x + k: 0 .. W + D - 2,
      // plus the kernels' read slack.
      const std::size_t len = static_cast<std::size_t>(max_width) + cost_stride_ + 64;
      w.lr_cost.assign(len, 0);
      w.lr_k.assign(len, 0);
      w.row_k.assign(static_cast<std::size_t>(max_width), 0);
    }
  }
}

void PathMatcher::release() {
  costs_.reset();
  preds_.reset();
  sum_.reset();
  costs_len_ = preds_len_ = 0;
  max_samples_ = 0;
  ring_capacity_ = 0;
  band_first_.reset();
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<RowCarry>().swap(carry_[pass]);
    std::vector<std::uint16_t>().swap(carry_paths_[pass]);
    std::vector<LargeArray<std::uint16_t>>().swap(path_rings_[pass]);
    std::vector<LargeArray<std::uint16_t>>().swap(path_mins_[pass]);
    wavefront_[pass].configure(1);
  }
  std::vector<std::uint32_t>().swap(p1_by_gap_);
  std::vector<std::uint32_t>().swap(p2_by_gap_);
  std::vector<std::uint16_t>().swap(zero_path_);
  std::vector<std::uint16_t>().swap(inv_pixels_q15_);
  std::vector<Worker>().swap(workers_);
  kernels_ = nullptr;
}

std::size_t PathMatcher::working_memory_bytes() const {
  const std::size_t bands = kernels_ != nullptr ? static_cast<std::size_t>(max_samples_ / max_width_) : 0;
  const std::size_t sum_len = kernels_ != nullptr ? static_cast<std::size_t>(max_samples_) * cost_stride_ : 0;
  std::size_t bytes = (costs_len_ + sum_len) * sizeof(std::uint16_t) + preds_len_ * sizeof(std::int32_t) +
                      capacity_bytes(inv_pixels_q15_) +
                      bands * (2 * 64 + sizeof(std::atomic<int>)) +  // the wavefronts, a cache line per band; band_first_
                      capacity_bytes(p1_by_gap_) + capacity_bytes(p2_by_gap_) + capacity_bytes(zero_path_) +
                      capacity_bytes(workers_);
  const auto ring = static_cast<std::size_t>(ring_capacity_);
  for (int pass = 0; pass < 2; ++pass) {
    bytes += capacity_bytes(carry_[pass]) + capacity_bytes(carry_paths_[pass]);
    bytes += path_rings_[pass].size() *
             ((ring * path_stride_ + 64 + ring) * sizeof(std::uint16_t) + 2 * sizeof(LargeArray<std::uint16_t>));
  }
  for (const Worker& w : workers_)
    bytes += (2 * path_stride_ + 64) * sizeof(std::uint16_t) + w.scratch.working_memory_bytes() +
             capacity_bytes(w.total) + capacity_bytes(w.slot_row) +
             capacity_bytes(w.lr_cost) + capacity_bytes(w.lr_k) + capacity_bytes(w.row_k) +
             (w.pixel_rows ? (ring_len_ + static_cast<std::size_t>(max_width_) * cost_stride_) *
                                 (byte_costs_ ? sizeof(std::uint8_t) : sizeof(std::uint16_t))
                           : 0);
  return bytes;
}

void PathMatcher::use_predecessors(const Mesh* mesh, const PredecessorTable& filled) {
  if (!filled.filled || filled.slots != preds_.get() || filled.directions != directions_) {
    supplied_for_ = nullptr;
    return;
  }
  supplied_for_ = mesh;
  supplied_reach_ = filled.reach;
  supplied_bounds_ = filled.bounds;
}

void PathMatcher::compute_costs(const MatchContext& ctx, const SampleLayout& samples, ThreadPool& pool) {
  // The predecessors first, on the first worker to arrive (they only read the
  // mesh, and write preds_), while the others start on the rows.
  // (Unless the mesher wrote them, and their bounds, while it built this
  // mesh: use_predecessors. Then there is no side task.)
  const bool supplied = !samples.dense() && supplied_for_ == samples.mesh;
  supplied_for_ = nullptr;
  side_next_.store(samples.dense() || supplied ? 1 : 0, std::memory_order_relaxed);
  int reach = supplied ? supplied_reach_ : 0;
  if (supplied) {
    reach_ = reach;
    bounds_ = supplied_bounds_;
  }
  preds_for_ = nullptr;
  const auto side_tasks = [&] {
    if (side_next_.fetch_add(1, std::memory_order_relaxed) != 0) return;
    reach_ = reach = find_predecessors(samples);
    bounds_ = predecessor_bounds(samples);
  };
  if (params_.cost.kind == CostKind::kCensus) {
    // Chunks of 16 rows. A chunk needs the window's rows above it, which its
    // worker's ring still holds when the worker's previous chunk ended there:
    // so the rings are emptied per frame, not per chunk, and each worker takes
    // the chunks of a band of its own first (HomeChunks), then the others'.
    for (Worker& w : workers_) std::fill(w.slot_row.begin(), w.slot_row.end(), -1);
    constexpr int kRowsPerChunk = 16;
    row_homes_.reset((samples.height + kRowsPerChunk - 1) / kRowsPerChunk, pool.size());
    pool.run([&](int w) {
      side_tasks();
      Worker& wk = workers_[static_cast<std::size_t>(w)];
      row_homes_.for_each(w, [&](int c) {
        const int y0 = c * kRowsPerChunk, y1 = std::min(samples.height, (c + 1) * kRowsPerChunk);
        const std::int64_t t0 = trace_ != nullptr ? monotonic_ns() : 0;
        if (byte_costs_)
          census_costs_by_rows<std::uint8_t>(ctx, samples, wk, y0, y1);
        else
          census_costs_by_rows<std::uint16_t>(ctx, samples, wk, y0, y1);
        if (trace_ != nullptr) trace_->record(w, TraceKind::kCostRows, t0, monotonic_ns(), y0, y1);
      });
    });
  } else {
    rows_.reset(0, samples.height, 4);
    pool.run([&](int w) {
      side_tasks();
      Worker& wk = workers_[static_cast<std::size_t>(w)];
      int y0 = 0, y1 = 0;
      while (rows_.next(&y0, &y1))
        for (int y = y0; y < y1; ++y)
          for (int i = samples.row_begin(y); i < samples.row_end(y); ++i)
            ctx.aggregate_sample(samples.x_of(i), y, costs_.get() + row(i, cost_stride_), wk.scratch);
    });
  }
  if (!samples.dense()) {
    check_reach(reach);
    preds_for_ = samples.mesh;
  }
}

// The census cost's box mean by rows: each image row's per-pixel Hamming costs
// are computed once per chunk into a ring of window_h rows; for an output row,
// the column sums over its (clipped) window rows, then each sample adds its
// (clipped) window columns and takes the mean by the model's Q32 rule. The
// same integer sums as MatchContext::aggregate_sample, with each pixel's
// popcounts done once instead of once per sample whose window holds it.
// T = std::uint8_t (byte_costs_) holds the same integers in half the bytes.
template <class T>
void PathMatcher::census_costs_by_rows(const MatchContext& ctx, const SampleLayout& samples, Worker& wk,
                                       int y0, int y1) {
  const int d = num_disp_;
  const int w = samples.width, h = samples.height;
  const int rx = params_.cost.window_w / 2, ry = params_.cost.window_h / 2;
  const int slots = params_.cost.window_h;
  const std::size_t row_len = static_cast<std::size_t>(max_width_) * cost_stride_;
  auto pixel_row = [&](int y) {
    const auto slot = static_cast<std::size_t>(y % slots);
    T* r = reinterpret_cast<T*>(wk.pixel_rows.get()) + slot * row_len;
    if (wk.slot_row[slot] != y) {
      ctx.census_pixel_costs(y, r, cost_stride_);
      wk.slot_row[slot] = y;
    }
    return r;
  };
  T* cols = reinterpret_cast<T*>(wk.column_sums.get());
  T* sum = reinterpret_cast<T*>(wk.total.data());
  std::uint8_t* const c_sums = reinterpret_cast<std::uint8_t*>(costs_.get());
  const T* parts[kMaxWindowSide];
  const T* cells[kMaxDirectCells];
  const auto sum_rows = [this](const T* const* rows, int count, std::size_t n, T* out) {
    if constexpr (sizeof(T) == 1)
      kernels_->sum_rows_u8(rows, count, n, out);
    else
      kernels_->sum_rows_u16(rows, count, n, out);
  };
  const int window_cells = params_.cost.window_w * params_.cost.window_h;
  for (int y = y0; y < y1; ++y) {
    const int samples_in_row = samples.row_end(y) - samples.row_begin(y);
    if (samples_in_row == 0) continue;
    const int wy0 = std::max(0, y - ry), wy1 = std::min(h - 1, y + ry);
    const int rows = wy1 - wy0 + 1;
    for (int yy = wy0; yy <= wy1; ++yy) parts[yy - wy0] = pixel_row(yy);
    // Column sums cost a row-wide pass of `rows` rows and then window_w per
    // sample; summing each sample's window cells directly costs window_w x
    // rows per sample. A row with few samples (sparse mode) takes the
    // direct sums: the same integers, added in another order.
    const bool direct = window_cells <= kMaxDirectCells &&
                        std::int64_t{samples_in_row} * params_.cost.window_w * (rows - 1) < std::int64_t{w} * rows;
    if (!direct) sum_rows(parts, rows, static_cast<std::size_t>(w) * cost_stride_, cols);
    for (int i = samples.row_begin(y); i < samples.row_end(y); ++i) {
      const int x = samples.x_of(i);
      const int wx0 = std::max(0, x - rx), wx1 = std::min(w - 1, x + rx);
      if constexpr (sizeof(T) == 1) {
        if (c_sums_u8_) sum = c_sums + row(i, cost_stride_);  // C is the sums
      }
      if (direct) {
        int c = 0;
        for (int r = 0; r < rows; ++r)
          for (int xx = wx0; xx <= wx1; ++xx) cells[c++] = parts[r] + static_cast<std::size_t>(xx) * cost_stride_;
        sum_rows(cells, c, static_cast<std::size_t>(d), sum);
      } else {
        const T* at[kMaxWindowSide];
        for (int xx = wx0; xx <= wx1; ++xx) at[xx - wx0] = cols + static_cast<std::size_t>(xx) * cost_stride_;
        sum_rows(at, wx1 - wx0 + 1, static_cast<std::size_t>(d), sum);
      }
      const auto pixels = static_cast<std::uint64_t>((wx1 - wx0 + 1) * (wy1 - wy0 + 1));
      std::uint16_t* cost_q4 = costs_.get() + row(i, cost_stride_);
      if constexpr (sizeof(T) == 1) {
        if (!c_sums_u8_) kernels_->normalize_costs_u8(sum, (std::uint64_t{1} << 32) / pixels, d, cost_q4);
      } else {
        kernels_->normalize_costs_u16(sum, (std::uint64_t{1} << 32) / pixels, d, cost_q4);
      }
    }
  }
}

namespace {

// find_predecessors' scan over the edges for kDirections path directions
// (known at compile time, so the 4-direction scan has no diagonal loop).
template <int kDirections>
int scan_mesh_edges(const Mesh& mesh, std::int32_t* preds) {
  constexpr auto per = static_cast<std::size_t>(kDirections - 2);
  const Vertex* v = mesh.vertices.data();
  const auto offer = [&](int p, int q, int px, int py, int first_dir) {
    const int dx = px - v[q].x, dy = py - v[q].y;
    std::int32_t* best_of_p = preds + static_cast<std::size_t>(p) * per;
    // Vertical (directions 2, 3): the dot product is |dy| > 0, and the larger
    // cosine is the smaller |dx| / |dy|, compared by cross-multiplication
    // (both below 2^12: exact in 32 bits).
    {
      std::int32_t& best = best_of_p[first_dir - 2];
      if (best < 0) {
        best = q;
      } else {
        const int bdx = px - v[best].x, bdy = py - v[best].y;
        const int lhs = std::abs(dx * bdy), rhs = std::abs(bdx * dy);
        if (lhs < rhs || (lhs == rhs && q < best)) best = q;
      }
    }
    for (int r = first_dir + 2; r < kDirections; r += 2) {
      const PathDirection u = kPathDirections[r];
      if (dx * u.dx + dy * u.dy <= 0) continue;
      std::int32_t& best = best_of_p[r - 2];
      if (best < 0) {
        best = q;
        continue;
      }
      const int bdx = px - v[best].x, bdy = py - v[best].y;
      if (follows_better(dx, dy, bdx, bdy, u) || (!follows_better(bdx, bdy, dx, dy, u) && q < best)) best = q;
    }
  };
  // Every triangle has positive orientation, so an edge inside the mesh is
  // listed once going down (its first vertex above) and once going up, by its
  // two triangles; an edge on the border only once: going down on the right
  // border x = W - 1, going up on the left one, x = 0 (the mesh covers the
  // image, Mesh's contract). Each edge is offered once: going down, or going
  // up on x = 0.
  int reach = 0;  // the largest id distance of an edge between two rows
  for (const Triangle& t : mesh.triangles) {
    const Vertex c[3] = {v[t[0]], v[t[1]], v[t[2]]};
    for (int e = 0; e < 3; ++e) {
      const int e1 = e == 2 ? 0 : e + 1;
      int a = t[static_cast<std::size_t>(e)], b = t[static_cast<std::size_t>(e1)];
      Vertex va = c[e], vb = c[e1];
      if (va.y >= vb.y) {
        if (va.y == vb.y || va.x != 0 || vb.x != 0) continue;
        std::swap(a, b), std::swap(va, vb);
      }
      // a above b
      reach = std::max(reach, b - a);
      offer(b, a, vb.x, vb.y, 2);  // forward directions (2, 4, 6): from above
      offer(a, b, va.x, va.y, 3);  // backward directions (3, 5, 7): from below
    }
  }
  return reach;
}

}  // namespace

// Sparse mode: the predecessor of p along a vertical or diagonal direction u is
// the mesh neighbour q on the side u comes from (q above p when u points
// down) with (p - q) . u > 0 that follows u best (largest cosine), ties to the
// smaller vertex id. Candidates come from the triangles' edges, so a vertex's
// neighbours are exactly its mesh neighbours (an interior edge is offered
// twice, which changes nothing).
int PathMatcher::find_predecessors(const SampleLayout& samples) {
  const int n = samples.count();
  const auto per = static_cast<std::size_t>(directions_ - 2);
  std::int32_t* preds = preds_.get();
  std::fill(preds, preds + static_cast<std::size_t>(n) * per, -1);
  return directions_ == 4 ? scan_mesh_edges<4>(*samples.mesh, preds) : scan_mesh_edges<8>(*samples.mesh, preds);
}

// The rings of run_pass hold ring_samples_ samples: enough for every tritree
// mesh. Another mesh whose edges reach further is refused before any pass.
void PathMatcher::check_reach(int reach) const {
  if (reach >= ring_capacity_)
    throw Error(ErrorCode::kInvalidArgument, "path matcher: a mesh edge spans " + std::to_string(reach) +
                                                 " samples, the path rings hold " + std::to_string(ring_capacity_) +
                                                 " (edges of at most tile side + 1 rows)");
}

int PathMatcher::predecessor(const SampleLayout& samples, int r, int i) const {
  const PathDirection u = kPathDirections[r];
  const int x = samples.x_of(i), y = samples.y_of(i);
  if (u.dy == 0) {  // horizontal: the neighbouring sample of the row
    const int q = i - u.dx;
    return (q >= samples.row_begin(y) && q < samples.row_end(y)) ? q : -1;
  }
  if (samples.dense()) {
    // The 8-neighbourhood under the same rule as the mesh: p - u when it is
    // inside; at the left/right border a diagonal falls back to the pixel
    // straight above/below (the only other neighbour with (p - q).u > 0).
    const int qy = y - u.dy;
    if (qy < 0 || qy >= samples.height) return -1;
    const int qx = (x - u.dx >= 0 && x - u.dx < samples.width) ? x - u.dx : x;
    return qy * samples.width + qx;
  }
  return predecessor_of_slot(
      preds_[static_cast<std::size_t>(i) * static_cast<std::size_t>(directions_ - 2) + static_cast<std::size_t>(r - 2)]);
}

PredecessorBounds PathMatcher::predecessor_bounds(const SampleLayout& samples) const {
  PredecessorBounds b;
  if (samples.dense()) {
    // The pixel above or below, and with 8 directions the diagonal ones: one
    // pixel ahead per row.
    b.reach_rows = 1;
    b.shear[0] = b.shear[1] = directions_ == 8 ? 1 : 0;
    return b;
  }
  widen_predecessor_bounds(preds_.get(), directions_ - 2, samples.mesh->vertices.data(), 0, samples.count(), 0, 1,
                           &b);
  return b;
}

// Tiles: a band of R rows cut into blocks of B pixels along the pass's x
// order u (x forward, W - 1 - x backward), each border moved back by `shear`
// pixels per row down the band. A predecessor q of p is at most reach_rows
// rows up and shear x (rows up) pixels ahead, so it lies in p's tile (an
// earlier row), a tile to its left, or a band above at most
// lead = ceil(shear R / B) tiles ahead per band: the wavefront's rule.
// Up to two workers, a pass is one worker's raster order (a band is a row, a
// tile the whole row): each pass keeps its path costs in its own core's
// caches, and the two passes meet in the middle. From three workers on, a
// pass has several: bands of 2 rows and about one tile a worker per band,
// wide enough that each row of a tile streams its costs and sums (16-pixel
// tiles made one worker's paths stage a quarter slower). The band height
// sets the rings: every band under way keeps its rows there, and a ring
// larger than the caches makes every path cost written a miss. One worker
// running the plan for 16 (synthetic D = 128) spent 9.3 ms in the path tiles
// with 2-row bands, 10.1 with 4, 10.6 with 8 and 13.1 with 16 (7.4 uncut);
// two workers running that plan, where a band's first row reads the row
// above from the other core, spent the same as one (one-row bands shared by
// two workers, where every row did, had taken the KITTI 000000 paths stage
// from 11.4 to 20.9 ms).
PathMatcher::PassPlan PathMatcher::plan_pass(const SampleLayout& samples, bool forward, int workers) const {
  PassPlan p;
  p.forward = forward;
  const int w = samples.width, h = samples.height;
  if (workers <= 2) {
    p.rows_per_band = 1;
    p.block = w;
  } else {
    p.rows_per_band = std::min(max_rows_per_band_, kMaxRowsPerBand);
    const int cols = std::clamp(workers, 2, std::max(2, w / 16));
    p.block = (w + cols - 1) / cols;
  }
  p.shear = bounds_.shear[forward ? 0 : 1];
  const int r = p.rows_per_band;
  p.bands = (h + r - 1) / r;
  p.cols = (w + p.block - 1) / p.block;
  p.lead = static_cast<int>(std::min<std::int64_t>(p.cols, (std::int64_t{p.shear} * r + p.block - 1) / p.block));
  // The ring holds, for the band being started, the rows of the bands still
  // under way and the rows their predecessors reach up: fewer bands under way
  // when a frame's rows would not fit (a mesh with long edges).
  const auto span = [&](int in_flight) {
    int most = 1;
    for (int k = 0; k < p.bands; ++k) {
      int y0 = 0, y1 = 0, e0 = 0, e1 = 0;
      band_rows(p, k, h, &y0, &y1);
      band_rows(p, std::max(0, k - in_flight + 1), h, &e0, &e1);
      const int first = forward ? std::max(0, e0 - bounds_.reach_rows) : y0;
      const int last = forward ? y1 - 1 : std::min(h - 1, e1 - 1 + bounds_.reach_rows);
      most = std::max(most, samples.row_end(last) - samples.row_begin(first) + 1);
    }
    return std::min(most, std::max(1, samples.count()));  // a slot per sample is always enough
  };
  p.in_flight = std::max(1, std::min(max_in_flight_, bands_in_flight(workers)));
  p.ring_n = span(p.in_flight);
  while (p.ring_n > ring_capacity_ && p.in_flight > 1) p.ring_n = span(--p.in_flight);
  if (p.ring_n > ring_capacity_)
    throw Error(ErrorCode::kInvalidArgument, "path matcher: mesh edges span " + std::to_string(bounds_.reach_rows) +
                                                 " rows, the path rings hold " + std::to_string(ring_capacity_) +
                                                 " samples (edges of at most tile side + 1 rows)");
  return p;
}

void PathMatcher::band_rows(const PassPlan& plan, int band, int height, int* y0, int* y1) {
  const int j = plan.forward ? band : plan.bands - 1 - band;
  *y0 = j * plan.rows_per_band;
  *y1 = std::min(height, *y0 + plan.rows_per_band);
}

void PathMatcher::run_tile(const SampleLayout& samples, ImageView<const std::uint8_t> gray, const PassPlan& plan,
                           int band, int col, int worker, int add) {
  Worker& wk = workers_[static_cast<std::size_t>(worker)];
  const KernelSet& ks = *kernels_;
  const bool forward = plan.forward;
  const int d = num_disp_;
  const int edge_scale = params_.paths.p2_edge_scale;
  const int pass = forward ? 0 : 1;
  const int others = directions_ / 2 - 1;  // vertical and diagonal directions of the pass
  std::uint16_t* paths[3] = {};
  std::uint16_t* mins[3] = {};
  for (int j = 0; j < others; ++j) {
    paths[j] = path_rings_[pass][static_cast<std::size_t>(j)].get();
    mins[j] = path_mins_[pass][static_cast<std::size_t>(j)].get();
  }
  std::uint16_t* ring[2] = {wk.row_path.get(), wk.row_path.get() + path_stride_};
  for (std::uint16_t* r : ring) {
    r[0] = kGuard;
    r[d + 1] = kGuard;
  }
  // P1 and P2 for the step q -> p (section 3b: by the edge's length, P2 >= P1,
  // and P2 shrunk across an intensity edge); ip, iq: I(p), I(q).
  auto penalties = [&](int px, int py, int ip, int qx, int qy, int iq, std::uint16_t* p1, std::uint16_t* p2) {
    if (!penalties_by_gap_) {
      *p1 = static_cast<std::uint16_t>(p1_by_gap_[1]);
      *p2 = p2_by_diff_[std::abs(ip - iq)];
      return;
    }
    const int gap = std::max(std::abs(px - qx), std::abs(py - qy));
    std::uint32_t a = p1_by_gap_[static_cast<std::size_t>(gap)];
    std::uint32_t b = p2_by_gap_[static_cast<std::size_t>(gap)];
    if (b < a) b = a;
    if (edge_scale > 0) {
      const auto di = static_cast<std::uint32_t>(std::abs(ip - iq));
      b = a + (b - a) * static_cast<std::uint32_t>(edge_scale) / (static_cast<std::uint32_t>(edge_scale) + di);
    }
    *p1 = static_cast<std::uint16_t>(a);
    *p2 = static_cast<std::uint16_t>(b);
  };
  const std::uint16_t* zero = zero_path_.data() + 1;
  const int ring_n = plan.ring_n;
  // Predecessors: the horizontal one is the row's previous sample in the
  // pass's order (carried from tile to tile); a mesh's others come from the
  // predecessor table, a dense frame's are the neighbouring pixels
  // (predecessor()'s rule, without its divisions).
  const bool dense = samples.dense();
  const int w = samples.width, h = samples.height;
  const Vertex* verts = dense ? nullptr : samples.mesh->vertices.data();
  const std::int32_t* preds = preds_.get();
  const auto per = static_cast<std::size_t>(directions_ - 2);
  const int di = forward ? 1 : -1;
  const std::size_t carry_base = static_cast<std::size_t>(band % plan.in_flight) * static_cast<std::size_t>(max_rows_per_band_);
  int band_y0 = 0, band_y1 = 0;
  band_rows(plan, band, h, &band_y0, &band_y1);
  // C and S of the samples ahead in the pass's order are prefetched: the
  // hardware prefetchers do not follow the backward pass's descending run of
  // samples (each a few ascending lines: at D = 128 on one Zen 4 worker the
  // backward pass took 10-17 ms against the forward pass's 4; with this 4 and
  // 3.5 ms), and in a tile narrower than the row each row's part starts far
  // from the last: the first samples of the next row's part are prefetched
  // when a row's part starts, the later ones kPrefetchSamples ahead (within
  // the row's part, unless the tiles are whole rows).
  const int ahead = di * kPrefetchSamples;
  const std::size_t cost_bytes = cost_stride_ * (c_sums_u8_ ? 1 : sizeof(std::uint16_t));  // a row of C
  const auto prefetch_sample = [&](int a) {
    prefetch_lines<0>(reinterpret_cast<const char*>(costs_.get()) + row(a, cost_bytes), cost_bytes);
    prefetch_lines<1>(sum_.get() + row(a, cost_stride_), cost_stride_ * sizeof(std::uint16_t));
  };
  // The first samples of row j's part of this tile (a row without samples:
  // none).
  const auto prefetch_row_start = [&](int j) {
    const int y = forward ? band_y0 + j : band_y1 - 1 - j;
    const int v0 = samples.row_begin(y), v1 = samples.row_end(y);
    if (v0 == v1) return;
    const int first = col == 0 ? (forward ? v0 : v1 - 1)
                               : carry_[pass][carry_base + static_cast<std::size_t>(j)].next;
    for (int a = first, k = 0; k < kPrefetchSamples && a >= v0 && a < v1; a += di, ++k) prefetch_sample(a);
  };
  const bool whole_rows = plan.cols == 1;
  prefetch_row_start(0);
  for (int j = 0; j < band_y1 - band_y0; ++j) {
    if (j + 1 < band_y1 - band_y0) prefetch_row_start(j + 1);
    const int y = forward ? band_y0 + j : band_y1 - 1 - j;
    const int v0 = samples.row_begin(y), v1 = samples.row_end(y);
    if (v0 == v1) continue;
    RowCarry& carry = carry_[pass][carry_base + static_cast<std::size_t>(j)];
    std::uint16_t* carry_path = carry_paths_[pass].data() + (carry_base + static_cast<std::size_t>(j)) * path_stride_;
    if (col == 0) {
      carry.next = forward ? v0 : v1 - 1;
      carry.hq_x = -1;
    }
    const int u_end = col + 1 == plan.cols ? w : (col + 1) * plan.block - plan.shear * j;
    int i = carry.next;
    const std::uint8_t* g = gray.row(y);
    const std::uint16_t* hprev = carry_path + 1;
    std::uint16_t hmin = carry.min;
    int hq_x = carry.hq_x, hq_i = carry.hq_i;
    int slot = i % ring_n;
    int step = 0;
    // Whole-row tiles continue into the next band's row in the same order.
    const int lo = whole_rows ? 0 : v0, hi = whole_rows ? samples.count() : v1;
    for (; forward ? i < v1 : i >= v0; i += di) {
      const int x = dense ? i - v0 : verts[i].x;
      if ((forward ? x : w - 1 - x) >= u_end) break;
      const int ip = g[x];
      std::uint16_t* sum = sum_.get() + row(i, cost_stride_);
      if (i + ahead >= lo && i + ahead < hi) prefetch_sample(i + ahead);
      // Step 0 is the horizontal path, 1 + k the k-th other direction of the
      // pass: all from their predecessors' L, in one kernel call.
      const std::uint16_t* prev[4] = {zero, zero, zero, zero};
      std::uint16_t* outs[4];
      std::uint16_t prev_min[4] = {}, p1[4] = {}, p2[4] = {}, step_min[4];
      outs[0] = ring[step & 1] + 1;
      if (hq_x >= 0) {
        penalties(x, y, ip, hq_x, y, hq_i, &p1[0], &p2[0]);
        prev[0] = hprev;
        prev_min[0] = hmin;
      }
      for (int k = 0; k < others; ++k) {
        const int rd = 2 * (k + 1) + pass;
        std::uint16_t* path = paths[k];
        std::uint16_t* o = path + row(slot, path_stride_);
        o[0] = kGuard;
        o[d + 1] = kGuard;
        int qr = -1, qx = 0, qy = 0;
        if (dense) {
          const PathDirection u = kPathDirections[rd];
          qy = y - u.dy;
          if (qy >= 0 && qy < h) {
            qx = x - u.dx >= 0 && x - u.dx < w ? x - u.dx : x;
            qr = qy * w + qx;
          }
        } else {
          qr = predecessor_of_slot(preds[static_cast<std::size_t>(i) * per + static_cast<std::size_t>(rd - 2)]);
          if (qr >= 0) {
            qx = verts[qr].x;
            qy = verts[qr].y;
          }
        }
        outs[1 + k] = o + 1;
        if (qr >= 0) {
          penalties(x, y, ip, qx, qy, gray.row(qy)[qx], &p1[1 + k], &p2[1 + k]);
          // |i - qr| < ring_n (plan_pass: the ring spans the rows predecessors reach).
          int qs = slot + (qr - i);
          if (qs < 0) qs += ring_n;
          else if (qs >= ring_n) qs -= ring_n;
          prev[1 + k] = path + row(qs, path_stride_) + 1;
          prev_min[1 + k] = mins[k][qs];
        }
      }
      if (c_sums_u8_) {
        ks.path_steps_u8(reinterpret_cast<const std::uint8_t*>(costs_.get()) + row(i, cost_stride_),
                         inv_pixels_q15_[box_pixels(samples, x, y)], prev, prev_min, p1, p2, 1 + others, d,
                         outs, sum, add, step_min);
      } else {
        ks.path_steps_u16(costs_.get() + row(i, cost_stride_), prev, prev_min, p1, p2, 1 + others, d, outs, sum,
                          add, step_min);
      }
      hmin = step_min[0];
      hprev = outs[0];
      ++step;
      for (int k = 0; k < others; ++k) mins[k][slot] = step_min[1 + k];
      hq_x = x;
      hq_i = ip;
      if (forward) slot = slot + 1 == ring_n ? 0 : slot + 1;
      else slot = slot == 0 ? ring_n - 1 : slot - 1;
    }
    carry.next = i;
    if (step > 0) {
      std::copy_n(hprev, d, carry_path + 1);
      carry.min = hmin;
      carry.hq_x = hq_x;
      carry.hq_i = hq_i;
    }
  }
}

void PathMatcher::aggregate(const SampleLayout& samples, ImageView<const std::uint8_t> left_gray,
                            ThreadPool& pool) {
  (void)aggregate_rows(samples, left_gray, pool, nullptr, nullptr);
}

PathMatcher::Rejected PathMatcher::aggregate_rows(const SampleLayout& samples,
                                                  ImageView<const std::uint8_t> left_gray, ThreadPool& pool,
                                                  std::int16_t* disp_q4, std::uint8_t* confidence) {
  if (samples.dense()) {
    bounds_ = predecessor_bounds(samples);
  } else if (preds_for_ != samples.mesh) {
    reach_ = find_predecessors(samples);
    check_reach(reach_);
    bounds_ = predecessor_bounds(samples);
  }
  preds_for_ = nullptr;  // the next frame finds its own
  const int workers = schedule_workers_;
  const PassPlan plans[2] = {plan_pass(samples, true, workers), plan_pass(samples, false, workers)};
  for (int pass = 0; pass < 2; ++pass)
    wavefront_[pass].reset(plans[pass].bands, plans[pass].cols, plans[pass].lead, plans[pass].in_flight);
  for (int j = 0; j < plans[0].bands; ++j) band_first_[j].store(-1, std::memory_order_relaxed);
  // Band j of image rows is pass 0's band j and pass 1's band bands - 1 - j.
  const auto image_band = [&](int pass, int band) { return pass == 0 ? band : plans[1].bands - 1 - band; };
  // A pass may start a band when it is the first to (it then writes S there),
  // or once the other pass has done it (it then adds to S).
  const auto may_start = [&](int pass, int band) {
    std::atomic<int>& first = band_first_[image_band(pass, band)];
    int f = first.load(std::memory_order_acquire);
    if (f < 0 && first.compare_exchange_strong(f, pass, std::memory_order_acq_rel)) return true;
    return f == pass || wavefront_[1 - pass].band_done(image_band(1 - pass, image_band(pass, band)));
  };
  const std::int64_t t_passes = trace_ != nullptr ? monotonic_ns() : 0;
  RejectedSum rejected;
  pool.run([&](int w) {
    RowDecider decide(*this, samples, workers_[static_cast<std::size_t>(w)], disp_q4, confidence);
    const int own = w & 1;  // even workers begin forward, odd ones backward
    // A pass cut into whole rows is one chain: a second worker on it would
    // only wait for the first and pull its rows across the cores, so with
    // such a plan each worker keeps to its own pass (one worker does both).
    const int passes_to_try = pool.size() == 1 || plans[1 - own].cols > 1 ? 2 : 1;
    for (int spins = 0;;) {
      int band = 0, col = 0, pass = -1;
      for (int q = 0; q < passes_to_try && pass < 0; ++q) {
        const int p = q == 0 ? own : 1 - own;
        if (wavefront_[p].try_next(&band, &col, [&](int k) { return may_start(p, k); })) pass = p;
      }
      if (pass < 0) {
        if (wavefront_[own].finished() && (passes_to_try == 1 || wavefront_[1 - own].finished())) break;
        if (++spins < 64) cpu_relax();
        else std::this_thread::yield();
        continue;
      }
      spins = 0;
      const int j = image_band(pass, band);
      const bool second = band_first_[j].load(std::memory_order_acquire) != pass;
      const std::int64_t t0 = trace_ != nullptr ? monotonic_ns() : 0;
      run_tile(samples, left_gray, plans[pass], band, col, w, second ? 1 : 0);
      const bool band_done = wavefront_[pass].finish(band, col);
      std::int64_t t1 = 0;
      if (trace_ != nullptr) {
        t1 = monotonic_ns();
        trace_->record(w, TraceKind::kPathTile, t0, t1, pass, band, col);
      }
      if (!band_done || !second || disp_q4 == nullptr) continue;
      // The band's S is complete: decide its rows while they are in cache.
      int y0 = 0, y1 = 0;
      band_rows(plans[pass], band, samples.height, &y0, &y1);
      for (int y = y0; y < y1; ++y) decide.row(y);
      if (trace_ != nullptr) trace_->record(w, TraceKind::kDecideBand, t1, monotonic_ns(), j);
    }
    if (disp_q4 != nullptr) rejected.add(decide.rejected);
  });
  if (trace_ != nullptr)
    trace_->record(FrameTrace::kPipelineTrack, TraceKind::kPaths, t_passes, monotonic_ns(), plans[0].cols,
                   plans[0].lead | plans[1].lead << 8, plans[0].rows_per_band);
  return rejected.total();
}

PathMatcher::Rejected PathMatcher::match(const SampleLayout& samples, ImageView<const std::uint8_t> left_gray,
                                         ThreadPool& pool, std::int16_t* disp_q4, std::uint8_t* confidence) {
  return aggregate_rows(samples, left_gray, pool, disp_q4, confidence);
}

// The pixels of the support box at (x, y) inside the image (census_costs_by_rows' clipped window).
std::size_t PathMatcher::box_pixels(const SampleLayout& samples, int x, int y) const {
  const int rx = params_.cost.window_w / 2, ry = params_.cost.window_h / 2;
  return static_cast<std::size_t>((std::min(samples.width - 1, x + rx) - std::max(0, x - rx) + 1) *
                                  (std::min(samples.height - 1, y + ry) - std::max(0, y - ry) + 1));
}

void PathMatcher::cost_q4(const SampleLayout& samples, int i, std::uint16_t* out) const {
  if (!c_sums_u8_) {
    std::copy_n(costs_.get() + row(i, cost_stride_), num_disp_, out);
    return;
  }
  const std::uint16_t inv = inv_pixels_q15_[box_pixels(samples, samples.x_of(i), samples.y_of(i))];
  const std::uint8_t* s = reinterpret_cast<const std::uint8_t*>(costs_.get()) + row(i, cost_stride_);
  for (int k = 0; k < num_disp_; ++k) out[k] = byte_mean_q4(s[k], inv);
}

void PathMatcher::summed_costs(int i, std::uint16_t* out) const {
  std::copy_n(sum_.get() + row(i, cost_stride_), num_disp_, out);
}

PathMatcher::RowDecider::RowDecider(const PathMatcher& pm, const SampleLayout& samples, Worker& wk,
                                    std::int16_t* disp_q4, std::uint8_t* confidence)
    : pm_(pm), samples_(samples), wk_(wk), disp_q4_(disp_q4), confidence_(confidence),
      lr_(pm.params_.validity.lr_max_diff_q4 >= 0 && pm.params_.validity.lr_source == LrSource::kSummedCosts) {}

void PathMatcher::RowDecider::row(int y) {
  const int v0 = samples_.row_begin(y), v1 = samples_.row_end(y);
  if (v0 == v1) return;
  begin_row(y);
  for (int i = v0; i < v1; ++i) sample(i, pm_.sum_.get() + PathMatcher::row(i, pm_.cost_stride_));
  end_row();
}

void PathMatcher::RowDecider::begin_row(int y) {
  v0_ = samples_.row_begin(y);
  v1_ = samples_.row_end(y);
  if (lr_)
    std::fill(wk_.lr_cost.begin(), wk_.lr_cost.begin() + (samples_.width + pm_.num_disp_ - 1), std::uint16_t{0xFFFF});
}

void PathMatcher::RowDecider::sample(int i, const std::uint16_t* s_row) {
  const int d = pm_.num_disp_;
  const int uniq = pm_.params_.validity.uniqueness_pct;
  std::uint16_t other = 0xFFFF;
  std::uint16_t *lr_cost = nullptr, *lr_k = nullptr;
  if (lr_) {
    const auto base = static_cast<std::size_t>(samples_.width - 1 - samples_.x_of(i));
    lr_cost = wk_.lr_cost.data() + base;
    lr_k = wk_.lr_k.data() + base;
  }
  const bool need_rival = uniq > 0 || confidence_ != nullptr;
  const int k = pm_.kernels_->winner_u16(s_row, d, need_rival ? &other : nullptr, lr_cost, lr_k);
  if (confidence_ != nullptr) confidence_[i] = measured_confidence(s_row[k], other);
  if (lr_) wk_.row_k[static_cast<std::size_t>(i - v0_)] = static_cast<std::uint16_t>(k);
  // Unique when every S(k') with |k' - k| > 1 has 100 S(k') > (100 + U) S(k):
  // the smallest of them (other) decides.
  if (uniq > 0 && (k > 1 || k + 2 < d) &&
      std::uint32_t{other} * 100u <= std::uint32_t{s_row[k]} * static_cast<std::uint32_t>(100 + uniq)) {
    disp_q4_[i] = kInvalidDispQ4;
    if (lr_) wk_.row_k[static_cast<std::size_t>(i - v0_)] = kNoWinner;
    ++rejected.uniqueness;
    return;
  }
  int off = 0;
  if (pm_.params_.dp.subpixel && k > 0 && k < d - 1)
    off = subpixel_offset_q4(pm_.params_.dp.subpixel_fit, s_row[k - 1], s_row[k], s_row[k + 1]);
  disp_q4_[i] = static_cast<std::int16_t>(kDispOne * (pm_.params_.d_min + k) + off);
}

// Left sample at x with winner k matches right pixel xr = x - d_min - k; the
// right view's winner there is lr_k at index W - 1 - x + k.
void PathMatcher::RowDecider::end_row() {
  if (!lr_) return;
  const int w = samples_.width;
  for (int i = v0_; i < v1_; ++i) {
    const int k = wk_.row_k[static_cast<std::size_t>(i - v0_)];
    if (k == kNoWinner) continue;
    const int x = samples_.x_of(i);
    const int xr = x - pm_.params_.d_min - k;
    bool ok = xr >= 0 && xr < w;
    if (ok) {
      const int kr = wk_.lr_k[static_cast<std::size_t>(w - 1 - x + k)];
      ok = kDispOne * std::abs(k - kr) <= pm_.params_.validity.lr_max_diff_q4;
    }
    if (!ok) {
      disp_q4_[i] = kInvalidDispQ4;
      ++rejected.left_right;
    }
  }
}

// Rows go to the workers on demand (the left-right check compares samples of
// one row); within a row the samples are taken left to right, so that
// winner_u16's `<` keeps the smallest k among equal costs at a right pixel.
PathMatcher::Rejected PathMatcher::select(const SampleLayout& samples, ThreadPool& pool,
                                          std::int16_t* disp_q4, std::uint8_t* confidence) {
  RejectedSum rejected;
  rows_.reset(0, samples.height, samples.dense() ? 4 : 16);
  pool.run([&](int wi) {
    Worker& wk = workers_[static_cast<std::size_t>(wi)];
    RowDecider decide(*this, samples, wk, disp_q4, confidence);
    int y0 = 0, y1 = 0;
    while (rows_.next(&y0, &y1))
      for (int y = y0; y < y1; ++y) decide.row(y);
    rejected.add(decide.rejected);
  });
  return rejected.total();
}

}  // namespace tristereo
