#include "src/aggregate/path_matcher.hpp"

#include <algorithm>
#include <cstdlib>
#include <string>

#include "src/dp/penalty.hpp"
#include "src/memory/capacity_bytes.hpp"
#include "src/dp/subpixel.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

namespace {
constexpr std::size_t kLanesRound = 16;  // rows start on 32-byte boundaries
constexpr std::uint16_t kGuard = 0xFFFF;
constexpr int kSamplesPerChunk = 1024;

std::size_t round_up(std::size_t v) { return (v + kLanesRound - 1) / kLanesRound * kLanesRound; }

// Storage that is not touched until a frame writes it (default-initialised).
template <class T>
std::unique_ptr<T[]> untouched(std::size_t n) {
  return std::unique_ptr<T[]>(new T[n]);
}
}  // namespace

void PathMatcher::configure(int max_width, int max_height, const StereoParams& params,
                            const KernelSet& kernels, int workers) {
  if (max_width < 2 || max_width > kMaxImageSide || max_height < 2 || max_height > kMaxImageSide)
    throw Error(ErrorCode::kInvalidArgument, "path matcher: maximum size " +
                                                 std::to_string(max_width) + "x" +
                                                 std::to_string(max_height) + " is outside 2.." +
                                                 std::to_string(kMaxImageSide));
  if (workers < 1 || workers > 256)
    throw Error(ErrorCode::kInvalidArgument, "path matcher: workers = " + std::to_string(workers));
  validate_params(params);
  if (!kernels.path_step_u16 || !kernels.sum_argmin_u16)
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
  max_width_ = max_width;
  const bool by_rows = params.cost.kind == CostKind::kCensus;
  ring_len_ = by_rows ? static_cast<std::size_t>(params.cost.window_h) * static_cast<std::size_t>(max_width) * cost_stride_ : 0;
  costs_len_ = n * cost_stride_;
  preds_len_ = n * 6;
  costs_ = untouched<std::uint16_t>(costs_len_);
  preds_ = untouched<std::int32_t>(preds_len_);
  zero_path_.assign(path_stride_, 0);
  zero_path_[0] = kGuard;
  zero_path_[static_cast<std::size_t>(d) + 1] = kGuard;
  workers_.clear();
  workers_.resize(static_cast<std::size_t>(workers));
  for (Worker& w : workers_) {
    w.path = untouched<std::uint16_t>(n * path_stride_);
    w.sum = untouched<std::uint16_t>(n * cost_stride_);
    w.path_min = untouched<std::uint16_t>(n);
    w.scratch.resize(d);
    w.total.assign(cost_stride_ + 64, 0);
    if (by_rows) {
      w.pixel_rows = untouched<std::uint16_t>(ring_len_);
      w.column_sums = untouched<std::uint16_t>(static_cast<std::size_t>(max_width) * cost_stride_);
      w.slot_row.assign(static_cast<std::size_t>(params.cost.window_h), -1);
    }
    w.terms.assign(static_cast<std::size_t>(workers), nullptr);
  }
}

void PathMatcher::release() {
  costs_.reset();
  preds_.reset();
  costs_len_ = preds_len_ = 0;
  max_samples_ = 0;
  std::vector<std::uint32_t>().swap(p1_by_gap_);
  std::vector<std::uint32_t>().swap(p2_by_gap_);
  std::vector<std::uint16_t>().swap(zero_path_);
  std::vector<Worker>().swap(workers_);
  kernels_ = nullptr;
}

std::size_t PathMatcher::working_memory_bytes() const {
  const auto n = static_cast<std::size_t>(max_samples_);
  std::size_t bytes = costs_len_ * sizeof(std::uint16_t) + preds_len_ * sizeof(std::int32_t) +
                      capacity_bytes(p1_by_gap_) + capacity_bytes(p2_by_gap_) + capacity_bytes(zero_path_) +
                      capacity_bytes(workers_);
  for (const Worker& w : workers_)
    bytes += (n * path_stride_ + n * cost_stride_ + n) * sizeof(std::uint16_t) + w.scratch.working_memory_bytes() +
             capacity_bytes(w.total) + capacity_bytes(w.terms) + capacity_bytes(w.slot_row) +
             (w.pixel_rows ? (ring_len_ + static_cast<std::size_t>(max_width_) * cost_stride_) * sizeof(std::uint16_t) : 0);
  return bytes;
}

void PathMatcher::compute_costs(const MatchContext& ctx, const SampleLayout& samples,
                                ThreadPool& pool) {
  if (params_.cost.kind == CostKind::kCensus) {
    // Larger chunks: each chunk recomputes the window's rows above and below it.
    rows_.reset(0, samples.height, 16);
    pool.run([&](int w) {
      Worker& wk = workers_[static_cast<std::size_t>(w)];
      int y0 = 0, y1 = 0;
      while (rows_.next(&y0, &y1)) census_costs_by_rows(ctx, samples, wk, y0, y1);
    });
    return;
  }
  rows_.reset(0, samples.height, 4);
  pool.run([&](int w) {
    Worker& wk = workers_[static_cast<std::size_t>(w)];
    int y0 = 0, y1 = 0;
    while (rows_.next(&y0, &y1))
      for (int y = y0; y < y1; ++y)
        for (int i = samples.row_begin(y); i < samples.row_end(y); ++i)
          ctx.aggregate_sample(samples.x_of(i), y, costs_.get() + row(i, cost_stride_), wk.scratch);
  });
}

// The census cost's box mean by rows: each image row's per-pixel Hamming costs
// are computed once per chunk into a ring of window_h rows; for an output row,
// the column sums over its (clipped) window rows, then each sample adds its
// (clipped) window columns and takes the mean by the model's Q32 rule. The
// same integer sums as MatchContext::aggregate_sample, with each pixel's
// popcounts done once instead of once per sample whose window holds it.
void PathMatcher::census_costs_by_rows(const MatchContext& ctx, const SampleLayout& samples, Worker& wk,
                                       int y0, int y1) {
  const int d = num_disp_;
  const int w = samples.width, h = samples.height;
  const int rx = params_.cost.window_w / 2, ry = params_.cost.window_h / 2;
  const int slots = params_.cost.window_h;
  const std::size_t row_len = static_cast<std::size_t>(max_width_) * cost_stride_;
  std::fill(wk.slot_row.begin(), wk.slot_row.end(), -1);
  auto pixel_row = [&](int y) {
    const auto slot = static_cast<std::size_t>(y % slots);
    std::uint16_t* r = wk.pixel_rows.get() + slot * row_len;
    if (wk.slot_row[slot] != y) {
      ctx.census_pixel_costs(y, r, cost_stride_, wk.scratch);
      wk.slot_row[slot] = y;
    }
    return r;
  };
  std::uint16_t* cols = wk.column_sums.get();
  std::uint16_t* sum = wk.total.data();
  for (int y = y0; y < y1; ++y) {
    if (samples.row_end(y) == samples.row_begin(y)) continue;
    const int wy0 = std::max(0, y - ry), wy1 = std::min(h - 1, y + ry);
    const std::uint16_t* first = pixel_row(wy0);
    std::copy(first, first + static_cast<std::size_t>(w) * cost_stride_, cols);
    for (int yy = wy0 + 1; yy <= wy1; ++yy) {
      const std::uint16_t* r = pixel_row(yy);
      for (std::size_t j = 0; j < static_cast<std::size_t>(w) * cost_stride_; ++j)
        cols[j] = static_cast<std::uint16_t>(cols[j] + r[j]);
    }
    for (int i = samples.row_begin(y); i < samples.row_end(y); ++i) {
      const int x = samples.x_of(i);
      const int wx0 = std::max(0, x - rx), wx1 = std::min(w - 1, x + rx);
      const std::uint16_t* c0 = cols + static_cast<std::size_t>(wx0) * cost_stride_;
      std::copy(c0, c0 + d, sum);
      for (int xx = wx0 + 1; xx <= wx1; ++xx) {
        const std::uint16_t* c = cols + static_cast<std::size_t>(xx) * cost_stride_;
        for (int k = 0; k < d; ++k) sum[k] = static_cast<std::uint16_t>(sum[k] + c[k]);
      }
      const auto pixels = static_cast<std::uint64_t>((wx1 - wx0 + 1) * (wy1 - wy0 + 1));
      kernels_->normalize_costs_u16(sum, (std::uint64_t{1} << 32) / pixels, d,
                                    costs_.get() + row(i, cost_stride_));
    }
  }
}

// Sparse mode: the predecessor of p along a vertical or diagonal direction u is
// the mesh neighbour q on the side u comes from (q above p when u points
// down) with (p - q) . u > 0 that follows u best (largest cosine), ties to the
// smaller vertex id. Candidates come from the triangles' edges, so a vertex's
// neighbours are exactly its mesh neighbours.
void PathMatcher::find_predecessors(const SampleLayout& samples) {
  const int n = samples.count();
  std::int32_t* preds = preds_.get();
  std::fill(preds, preds + static_cast<std::size_t>(n) * 6, -1);
  const std::vector<Vertex>& v = samples.mesh->vertices;
  auto offer = [&](int p, int q, int first_dir) {
    const int dx = v[static_cast<std::size_t>(p)].x - v[static_cast<std::size_t>(q)].x;
    const int dy = v[static_cast<std::size_t>(p)].y - v[static_cast<std::size_t>(q)].y;
    for (int r = first_dir; r < directions_; r += 2) {
      const PathDirection u = kPathDirections[r];
      if (dx * u.dx + dy * u.dy <= 0) continue;
      std::int32_t& best = preds[static_cast<std::size_t>(r - 2) * static_cast<std::size_t>(n) + static_cast<std::size_t>(p)];
      if (best < 0) {
        best = q;
        continue;
      }
      const int bdx = v[static_cast<std::size_t>(p)].x - v[static_cast<std::size_t>(best)].x;
      const int bdy = v[static_cast<std::size_t>(p)].y - v[static_cast<std::size_t>(best)].y;
      if (follows_better(dx, dy, bdx, bdy, u) ||
          (!follows_better(bdx, bdy, dx, dy, u) && q < best))
        best = q;
    }
  };
  for (const Triangle& t : samples.mesh->triangles)
    for (int e = 0; e < 3; ++e) {
      int a = t[static_cast<std::size_t>(e)], b = t[static_cast<std::size_t>((e + 1) % 3)];
      const int ya = v[static_cast<std::size_t>(a)].y, yb = v[static_cast<std::size_t>(b)].y;
      if (ya == yb) continue;
      if (ya > yb) std::swap(a, b);  // a above b
      offer(b, a, 2);  // forward directions (2, 4, 6): from above
      offer(a, b, 3);  // backward directions (3, 5, 7): from below
    }
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
  return preds_[static_cast<std::size_t>(r - 2) * static_cast<std::size_t>(samples.count()) + static_cast<std::size_t>(i)];
}

void PathMatcher::run_direction(const SampleLayout& samples, ImageView<const std::uint8_t> gray,
                                int r, int worker, bool accumulate) {
  Worker& wk = workers_[static_cast<std::size_t>(worker)];
  const KernelSet& ks = *kernels_;
  const int n = samples.count();
  const int d = num_disp_;
  const int edge_scale = params_.paths.p2_edge_scale;
  const bool forward = path_runs_forward(r);
  std::uint16_t* path = wk.path.get();
  std::uint16_t* path_min = wk.path_min.get();
  for (int step = 0; step < n; ++step) {
    const int i = forward ? step : n - 1 - step;
    std::uint16_t* out = path + row(i, path_stride_);
    out[0] = kGuard;
    out[d + 1] = kGuard;
    const int q = predecessor(samples, r, i);
    const std::uint16_t* prev = zero_path_.data() + 1;
    std::uint16_t prev_min = 0, p1 = 0, p2 = 0;
    if (q >= 0) {
      const int px = samples.x_of(i), py = samples.y_of(i);
      const int qx = samples.x_of(q), qy = samples.y_of(q);
      const int gap = std::max(std::abs(px - qx), std::abs(py - qy));
      std::uint32_t a = p1_by_gap_[static_cast<std::size_t>(gap)];
      std::uint32_t b = p2_by_gap_[static_cast<std::size_t>(gap)];
      if (b < a) b = a;
      if (edge_scale > 0) {
        const std::uint32_t di = static_cast<std::uint32_t>(std::abs(gray.row(py)[px] - gray.row(qy)[qx]));
        b = a + (b - a) * static_cast<std::uint32_t>(edge_scale) / (static_cast<std::uint32_t>(edge_scale) + di);
      }
      prev = path + row(q, path_stride_) + 1;
      prev_min = path_min[q];
      p1 = static_cast<std::uint16_t>(a);
      p2 = static_cast<std::uint16_t>(b);
    }
    path_min[i] = ks.path_step_u16(costs_.get() + row(i, cost_stride_), prev, prev_min, p1, p2, d,
                                   out + 1, wk.sum.get() + row(i, cost_stride_), accumulate ? 1 : 0);
  }
}

void PathMatcher::aggregate(const SampleLayout& samples, ImageView<const std::uint8_t> left_gray,
                            ThreadPool& pool) {
  if (!samples.dense()) find_predecessors(samples);
  for (Worker& w : workers_) w.has_sum = false;
  dirs_.reset(0, directions_, 1);
  pool.run([&](int w) {
    Worker& wk = workers_[static_cast<std::size_t>(w)];
    int r0 = 0, r1 = 0;
    while (dirs_.next(&r0, &r1))
      for (int r = r0; r < r1; ++r) {
        run_direction(samples, left_gray, r, w, wk.has_sum);
        wk.has_sum = true;
      }
  });
}

void PathMatcher::summed_costs(int i, std::uint16_t* out) const {
  for (int k = 0; k < num_disp_; ++k) {
    std::uint32_t s = 0;
    for (const Worker& w : workers_)
      if (w.has_sum) s += w.sum[row(i, cost_stride_) + static_cast<std::size_t>(k)];
    out[k] = static_cast<std::uint16_t>(s);
  }
}

int PathMatcher::select(const SampleLayout& samples, ThreadPool& pool, std::int16_t* disp_q4) {
  const int n = samples.count();
  const int d = num_disp_;
  const int uniq = params_.validity.uniqueness_pct;
  const bool subpixel = params_.dp.subpixel;
  std::atomic<int> rejected{0};
  chunks_.reset(0, n, kSamplesPerChunk);
  pool.run([&](int w) {
    Worker& wk = workers_[static_cast<std::size_t>(w)];
    int count = 0;
    for (const Worker& o : workers_)
      if (o.has_sum) wk.terms[static_cast<std::size_t>(count++)] = nullptr;
    int local_rejected = 0;
    int i0 = 0, i1 = 0;
    std::uint16_t* total = wk.total.data();
    while (chunks_.next(&i0, &i1))
      for (int i = i0; i < i1; ++i) {
        int t = 0;
        for (const Worker& o : workers_)
          if (o.has_sum) wk.terms[static_cast<std::size_t>(t++)] = o.sum.get() + row(i, cost_stride_);
        const int k = kernels_->sum_argmin_u16(wk.terms.data(), count, d, total);
        if (uniq > 0) {
          const std::uint32_t limit = std::uint32_t{total[k]} * static_cast<std::uint32_t>(100 + uniq);
          bool unique = true;
          for (int j = 0; j < d && unique; ++j)
            if ((j < k - 1 || j > k + 1) && std::uint32_t{total[j]} * 100u <= limit) unique = false;
          if (!unique) {
            disp_q4[i] = kInvalidDispQ4;
            ++local_rejected;
            continue;
          }
        }
        int off = 0;
        if (subpixel && k > 0 && k < d - 1) off = subpixel_offset_q4(total[k - 1], total[k], total[k + 1]);
        disp_q4[i] = static_cast<std::int16_t>(kDispOne * (params_.d_min + k) + off);
      }
    rejected.fetch_add(local_rejected, std::memory_order_relaxed);
  });
  return rejected.load();
}

}  // namespace tristereo
