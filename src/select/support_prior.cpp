#include "src/select/support_prior.hpp"

#include <algorithm>
#include <climits>
#include <cstdlib>

#include "platform/clock.hpp"
#include "platform/thread_pool.hpp"
#include "src/dp/subpixel.hpp"
#include "src/kernels/kernel_set.hpp"
#include "src/select/confidence.hpp"
#include "src/select/plane_fit.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/trace.hpp"

namespace tristereo {

namespace {
constexpr std::uint8_t kSupport = 1, kCovered = 2;
// Work items on the pool: segment roots, and samples decided again (a few
// tens of microseconds each on a KITTI frame).
constexpr int kRootsPerChunk = 2048;
constexpr int kRedoPerChunk = 256;
}  // namespace

void SupportPrior::configure(int max_samples, int max_triangles, int max_disp, int workers) {
  const auto n = static_cast<std::size_t>(max_samples);
  // A triangulation of n samples, b of them on the border, has 2 n - 2 - b
  // triangles: their 3 (2 n - 2 - b) edges and the b border edges written
  // again stay below 6 n.
  edge_cap_ = 3 * std::max(max_triangles, 2 * max_samples);
  edges_ = large_array<Edge>(static_cast<std::size_t>(edge_cap_));
  fit_ = large_array<FitPoint>(n);
  prior_ = large_array<std::int32_t>(n);
  cand_ = large_array<std::int32_t>(n);
  pending_ = large_array<std::int32_t>(n);
  parent_ = large_array<std::int32_t>(n);
  count_ = large_array<std::int32_t>(n + 1);
  order_ = large_array<std::int32_t>(n);
  inten_ = large_array<std::uint8_t>(n);
  flags_ = large_array<std::uint8_t>(n);
  max_disp_ = max_disp;
  workers = std::max(1, workers);
  s2_.assign(static_cast<std::size_t>(max_disp) * static_cast<std::size_t>(workers), 0);
  penalty_.assign(2 * static_cast<std::size_t>(max_disp), 0);
  worker_counts_.assign(static_cast<std::size_t>(workers), SupportPriorCounts{});
  bytes_ = (6 * n + 1) * sizeof(std::int32_t) + static_cast<std::size_t>(edge_cap_) * sizeof(Edge) + n * sizeof(FitPoint) + 2 * n +
           2 * static_cast<std::size_t>(max_disp) * static_cast<std::size_t>(workers + 2) +
           static_cast<std::size_t>(workers) * sizeof(SupportPriorCounts);
}

void SupportPrior::release() {
  for (LargeArray<std::int32_t>* a : {&prior_, &cand_, &pending_, &parent_, &count_, &order_})
    *a = LargeArray<std::int32_t>{};
  inten_ = LargeArray<std::uint8_t>{};
  flags_ = LargeArray<std::uint8_t>{};
  edges_ = LargeArray<Edge>{};
  edge_cap_ = n_edges_ = 0;
  fit_ = LargeArray<FitPoint>{};
  s2_ = std::vector<std::uint16_t>{};
  penalty_ = std::vector<std::uint16_t>{};
  worker_counts_ = std::vector<SupportPriorCounts>{};
  bytes_ = 0;
  max_disp_ = 0;
}

int SupportPrior::find(int a) {
  std::int32_t* parent = parent_.get();
  while (parent[a] != a) {
    parent[a] = parent[parent[a]];
    a = parent[a];
  }
  return a;
}

void SupportPrior::planes(const StereoParams& params, const SampleLayout& samples, const std::int16_t* disp,
                          int tau, int joined, ThreadPool* pool, FrameTrace* trace) {
  const int n = n_;
  const SupportPriorParams& pp = params.prior;
  std::int32_t* parent = parent_.get();
  std::uint8_t* flags = flags_.get();
  // Segments: the components of the mesh edges with |dI| <= tau; each one's
  // root is its smallest sample (the larger root goes under the smaller: the
  // partition and its roots do not depend on the order of the edges).
  // joined >= 0: parent holds the segments of that smaller threshold (a
  // finer partition), so only the edges with joined < |dI| <= tau remain.
  if (joined < 0)
    for (int i = 0; i < n; ++i) parent[i] = i;
  const Edge* edges = edges_.get();
  for (int j = 0; j < n_edges_; ++j) {
    const Edge e = edges[j];
    if (e.di > tau || e.di <= joined) continue;
    const int a = find(e.a), b = find(e.b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
  // Members grouped by segment (counting sort by root, ascending ids).
  std::int32_t* count = count_.get();
  std::int32_t* order = order_.get();
  std::fill_n(count, n + 1, 0);
  for (int i = 0; i < n; ++i) {
    parent[i] = find(i);
    ++count[parent[i] + 1];
  }
  for (int r = 0; r < n; ++r) count[r + 1] += count[r];
  // count[r] = the segment's first slot; cand_ holds the running slot.
  std::int32_t* next = cand_.get();
  std::copy_n(count, n, next);
  for (int i = 0; i < n; ++i) order[next[parent[i]]++] = i;
  const std::int64_t tol = pp.plane_tol_q4;
  // Segment r (its members order[count[r] .. count[r + 1])): true when it
  // gets a plane. Segments share no sample, and each gathers its support
  // points in its own slots of fit_, so they may go to any worker.
  const auto fit_segment = [&](int r) {
    const int g0 = count[r], g1 = count[r + 1];
    if (g1 - g0 < 2) return false;  // a plane needs support and another sample to give to
    int support = 0;
    bool other = false;
    for (int j = g0; j < g1; ++j) {
      const std::uint8_t f = flags[order[j]];
      if (f & kSupport) ++support;
      else if (!(f & kCovered)) other = true;
    }
    if (!other || support < pp.plane_min) return false;
    // The segment's support points, in order, gathered once for the fits.
    FitPoint* pts = fit_.get() + g0;
    int np = 0;
    for (int j = g0; j < g1; ++j) {
      const int i = order[j];
      if (flags[i] & kSupport) pts[np++] = FitPoint{samples.x_of(i), samples.y_of(i), disp[i]};
    }
    IntPlane plane;
    bool ok = true;
    // Fit 0 on every support sample, fits 1..3 on those within 2 tol of the previous plane.
    for (int fit = 0; fit < 4 && ok; ++fit) {
      PlaneSums sums;
      for (int j = 0; j < np; ++j) {
        const FitPoint p = pts[j];
        if (fit > 0 && abs64(plane.at(p.x, p.y) - p.d) > 2 * tol) continue;
        sums.add(p.x, p.y, p.d);
      }
      if (sums.n < 3) {
        ok = false;
        break;
      }
      IntPlane next_plane;
      next_plane.xbar = static_cast<int>(floor_div(sums.sx, sums.n));
      next_plane.ybar = static_cast<int>(floor_div(sums.sy, sums.n));
      next_plane.dbar = static_cast<int>(floor_div(sums.sd, sums.n));
      const PlaneMoments m = sums.moments(next_plane.xbar, next_plane.ybar, next_plane.dbar);
      ok = solve_plane(m, sums.n, &next_plane);
      plane = next_plane;
    }
    if (!ok) return false;
    // Accepted when at least half the support lies within tol and the
    // residuals, each capped at 2 tol, have a mean square of at most tol^2.
    std::int64_t inliers = 0, sq = 0;
    for (int j = 0; j < np; ++j) {
      const FitPoint p = pts[j];
      const std::int64_t e = abs64(plane.at(p.x, p.y) - p.d);
      if (e <= tol) ++inliers;
      sq += std::min(e * e, 4 * tol * tol);
    }
    if (2 * inliers < support || sq > tol * tol * support) return false;
    const int lo = kDispOne * params.d_min, hi = kDispOne * (params.d_min + params.num_disp - 1);
    for (int j = g0; j < g1; ++j) {
      const int i = order[j];
      if (flags[i] & (kSupport | kCovered)) continue;
      flags[i] |= kCovered;
      prior_.get()[i] = std::clamp(plane.at(samples.x_of(i), samples.y_of(i)), lo, hi);
    }
    return true;
  };
  for_chunks(pool, trace, TraceKind::kPriorSegments, tau, n, kRootsPerChunk, [&](int w, int r0, int r1) {
    for (int r = r0; r < r1; ++r) worker_counts_[static_cast<std::size_t>(w)].planes += fit_segment(r) ? 1 : 0;
  });
}

template <class Body>
void SupportPrior::for_chunks(ThreadPool* pool, FrameTrace* trace, TraceKind kind, int tag, int n, int chunk,
                              Body body) {
  const auto traced = [&](int w, int j0, int j1) {
    const std::int64_t t0 = trace != nullptr ? monotonic_ns() : 0;
    body(w, j0, j1);
    if (trace != nullptr) trace->record(w, kind, t0, monotonic_ns(), j0, j1, tag);
  };
  if (pool == nullptr || pool->size() < 2 || n < 2 * chunk) {
    if (n > 0) traced(0, 0, n);
    return;
  }
  chunks_.reset(0, n, chunk);
  pool->run([&](int w) {
    if (w >= static_cast<int>(worker_counts_.size())) return;
    int j0 = 0, j1 = 0;
    while (chunks_.next(&j0, &j1)) traced(w, j0, j1);
  });
}

SupportPriorCounts SupportPrior::apply(const StereoParams& params, const SampleLayout& samples,
                                       const PathMatcher& pm, ImageView<const std::uint8_t> left,
                                       std::int16_t* disp, std::uint8_t* conf, const KernelSet& ks,
                                       ThreadPool* pool, FrameTrace* trace) {
  SupportPriorCounts counts;
  const SupportPriorParams& pp = params.prior;
  if (pp.lambda_q4 <= 0 || samples.dense()) return counts;
  const Mesh& mesh = *samples.mesh;
  const int n = samples.count();
  n_ = n;
  std::uint8_t* inten = inten_.get();
  std::uint8_t* flags = flags_.get();
  std::int32_t* prior = prior_.get();
  std::int32_t* pending = pending_.get();
  for (int i = 0; i < n; ++i) {
    inten[i] = left.row(samples.y_of(i))[samples.x_of(i)];
    const bool support = disp[i] != kInvalidDispQ4 && conf[i] >= pp.support_conf;
    flags[i] = support ? kSupport : 0;
    if (support) ++counts.support;
  }
  // The mesh edges the segment levels use (|dI| <= the larger threshold),
  // each once. The mesh is conforming and its triangles turn one way, so an
  // inner edge comes as (a, b) from one triangle and (b, a) from the other:
  // (a, b) with a < b is kept. A border edge has one triangle, and the
  // frame's sides are cut exactly at their samples: the pairs of samples
  // next to each other along a side are added again (twice changes nothing
  // in the union-find). Each is written and counted when kept (a branch
  // here mispredicts on a third of the edges).
  {
    const int most = std::max(pp.seg_fine, pp.seg_coarse);
    Edge* edges = edges_.get();
    int lo = 0;
    const auto add = [&](int a, int b, int keep) {
      const int di = std::abs(inten[a] - inten[b]);
      keep &= di <= most;
      edges[lo] = Edge{a, b, di};  // lo < edge_cap_: fewer are written
      lo += keep;
    };
    if (most > 0) {
      for (const Triangle& t : mesh.triangles)
        for (int e = 0; e < 3; ++e) {
          const int a = t[static_cast<std::size_t>(e)], b = t[static_cast<std::size_t>((e + 1) % 3)];
          add(a, b, a < b);
        }
      const int h = left.height;
      for (int y : {0, h - 1})  // along the top and bottom rows
        for (int i = samples.row_begin(y); i + 1 < samples.row_begin(y + 1); ++i) add(i, i + 1, 1);
      int prev_left = -1, prev_right = -1;  // along the left and right columns
      for (int y = 0; y < h; ++y) {
        const int first = samples.row_begin(y), last = samples.row_begin(y + 1) - 1;
        if (last < first) continue;
        if (samples.x_of(first) == 0) {
          if (prev_left >= 0) add(prev_left, first, 1);
          prev_left = first;
        }
        if (samples.x_of(last) == left.width - 1) {
          if (prev_right >= 0) add(prev_right, last, 1);
          prev_right = last;
        }
      }
    }
    n_edges_ = lo;
  }
  // Planes: the fine level, then the coarse one for samples still uncovered.
  for (SupportPriorCounts& c : worker_counts_) c = SupportPriorCounts{};
  if (pp.seg_fine > 0) planes(params, samples, disp, pp.seg_fine, -1, pool, trace);
  if (pp.seg_coarse > 0)
    planes(params, samples, disp, pp.seg_coarse, pp.seg_fine > 0 && pp.seg_coarse >= pp.seg_fine ? pp.seg_fine : -1,
           pool, trace);
  // Pass 2 on the summed costs. S'(k) = S(k) + pen(k - kp), pen(j) =
  // lambda min(|j|, T): the table penalty_[j + D - 1] holds it saturated
  // to 16 bits, and the kernels take S' saturated too. S'(k') <= S(kp) <=
  // 65534 never saturates, so the winner is exact; the rival is exact unless
  // it saturated (then it is found again in 32 bits), and the sub-pixel fit
  // takes its two neighbours unsaturated.
  const int d = params.num_disp, dmin = params.d_min;
  const std::uint32_t lambda = static_cast<std::uint32_t>(pp.lambda_q4);
  const int conf_cap = std::max<int>(kMinMeasuredConfidence, pp.support_conf - 1);
  std::uint16_t* penalty = penalty_.data();
  for (int j = 0; j < 2 * d - 1; ++j)
    penalty[j] = static_cast<std::uint16_t>(
        std::min<std::uint32_t>(0xFFFFu, lambda * static_cast<std::uint32_t>(std::min(std::abs(j - (d - 1)), pp.trunc))));
  // The samples to decide again, listed first: their rows of S are far
  // apart in memory, and each is prefetched a few samples ahead. Each
  // sample writes only its own outputs, so the list may be shared.
  int n_redo = 0;
  for (int i = 0; i < n; ++i)
    if (flags[i] & kCovered) pending[n_redo++] = i;
  constexpr int kAhead = 8;
  const std::size_t row_bytes = static_cast<std::size_t>(d) * sizeof(std::uint16_t);
  for_chunks(pool, trace, TraceKind::kPriorSamples, 0, n_redo, kRedoPerChunk, [&](int w, int j0, int j1) {
    std::uint16_t* s2 = s2_.data() + static_cast<std::size_t>(w) * static_cast<std::size_t>(max_disp_);
    SupportPriorCounts& wc = worker_counts_[static_cast<std::size_t>(w)];
    for (int j = j0; j < j1; ++j) {
      if (j + kAhead < j1) {
        const char* ahead = reinterpret_cast<const char*>(pm.summed_costs_row(pending[j + kAhead]));
        for (std::size_t b = 0; b < row_bytes; b += 64) __builtin_prefetch(ahead + b);
      }
      const int i = pending[j];
      ++wc.redecided;
      const std::uint16_t* s = pm.summed_costs_row(i);
      const int kp = std::clamp(static_cast<int>(floor_div(prior[i] + 8, kDispOne)) - dmin, 0, d - 1);
      const auto exact = [&](int q) {
        return s[q] + lambda * static_cast<std::uint32_t>(std::min(std::abs(q - kp), pp.trunc));
      };
      ks.add_saturate_u16(s, penalty + (d - 1 - kp), d, s2);
      std::uint16_t rival16 = 0xFFFF;
      const int k = ks.winner_u16(s2, d, &rival16, nullptr, nullptr);
      const std::uint32_t best = s2[k];
      const bool any_rival = k > 1 || k + 2 < d;
      std::uint32_t rival = rival16;
      if (any_rival && rival16 == 0xFFFFu) {
        rival = 0xFFFFFFFFu;
        for (int q = 0; q < d; ++q)
          if (q < k - 1 || q > k + 1) rival = std::min(rival, exact(q));
      }
      if (pp.uniqueness_pct > 0 && any_rival &&
          std::uint64_t{rival} * 100u <= std::uint64_t{best} * static_cast<std::uint64_t>(100 + pp.uniqueness_pct)) {
        disp[i] = kInvalidDispQ4;
        ++wc.rejected;
        continue;
      }
      int off = 0;
      if (params.dp.subpixel && k > 0 && k < d - 1)
        off = subpixel_offset_q4(params.dp.subpixel_fit, static_cast<int>(exact(k - 1)), static_cast<int>(best),
                                 static_cast<int>(exact(k + 1)));
      disp[i] = static_cast<std::int16_t>(kDispOne * (dmin + k) + off);
      conf[i] = static_cast<std::uint8_t>(std::min<int>(conf_cap, measured_confidence(best, rival)));
    }
  });
  for (const SupportPriorCounts& c : worker_counts_) {
    counts.redecided += c.redecided;
    counts.rejected += c.rejected;
    counts.planes += c.planes;
  }
  return counts;
}

}  // namespace tristereo
