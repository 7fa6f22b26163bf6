#include "src/select/support_prior.hpp"

#include <algorithm>
#include <climits>
#include <cstdlib>

#include "platform/clock.hpp"
#include "platform/prefetch.hpp"
#include "platform/thread_pool.hpp"
#include "src/dp/subpixel.hpp"
#include "src/kernels/kernel_set.hpp"
#include "src/kernels/kernels_scalar.hpp"
#include "src/select/confidence.hpp"
#include "src/select/plane_fit.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/trace.hpp"

namespace tristereo {

namespace {
constexpr std::uint8_t kSupport = 1, kCovered = 2;
// Work items on the pool (a few tens of microseconds each on a KITTI frame):
// samples (set-up, roots), triangles (joins), segment roots (planes) and
// samples decided again.
constexpr int kSamplesPerChunk = 8192;
constexpr int kTrianglesPerChunk = 4096;
constexpr int kRootsPerChunk = 2048;
// A segment this large is fitted with its members in chunks on every worker.
constexpr int kBigSegment = 2048;
constexpr int kBigChunk = 1024;
constexpr int kRedoPerChunk = 256;
// Below this many workers one thread sorts faster than several with atomic
// counts (a few per cent of the stage on two).
constexpr int kSharedSortWorkers = 4;

// parent[] is shared by the workers while they join segments: every access
// is atomic (relaxed: each link and each shortcut only ever points a sample
// at one of its ancestors, a smaller sample, whatever the others do).
std::int32_t load(const std::int32_t* p) { return __atomic_load_n(p, __ATOMIC_RELAXED); }
void store(std::int32_t* p, std::int32_t v) { __atomic_store_n(p, v, __ATOMIC_RELAXED); }

// One step of Rem's union with splicing, for one thread alone: of a and b,
// the sample with the larger parent is hung under the other's parent, and
// the union goes on (true) from its old parent and the other sample, left
// in *a and *b. Without a branch: when both parents are equal the store
// writes the parent the sample has. Every parent stays at most its sample.
inline bool rem_step(std::int32_t* parent, std::int32_t* a, std::int32_t* b) {
  const std::int32_t pa = parent[*a], pb = parent[*b];
  const bool b_higher = pa < pb;
  const std::int32_t x = b_higher ? *b : *a, px = b_higher ? pb : pa;
  const std::int32_t y = b_higher ? *a : *b, py = b_higher ? pa : pb;
  parent[x] = py;
  *a = px;
  *b = y;
  return (pa != pb) & (x != px);
}
}  // namespace

void SupportPrior::configure(int max_samples, int max_triangles, int max_disp, int workers, int schedule_workers) {
  const auto n = static_cast<std::size_t>(max_samples);
  fit_ = large_array<FitPoint>(n);
  prior_ = large_array<std::int16_t>(n);
  parent_ = large_array<std::int32_t>(n);
  count_ = large_array<std::int32_t>(n + 2);
  order_ = large_array<std::int32_t>(n);
  inten_ = large_array<std::uint8_t>(n);
  members_ = large_array<Member>(n);
  next_ = large_array<std::uint8_t>(static_cast<std::size_t>(max_triangles));
  max_disp_ = max_disp;
  workers = std::max(1, workers);
  s2_.assign(static_cast<std::size_t>(max_disp) * static_cast<std::size_t>(workers), 0);
  penalty_.assign(2 * static_cast<std::size_t>(max_disp), 0);
  worker_counts_.assign(static_cast<std::size_t>(workers), SupportPriorCounts{});
  big_.assign(n / kBigSegment + 1, 0);
  big_points_.assign(n / kBigChunk + 1, 0);
  big_census_.assign(static_cast<std::size_t>(workers), Census{});
  big_sums_.assign(static_cast<std::size_t>(workers), PlaneSums{});
  big_residuals_.assign(static_cast<std::size_t>(workers), Residuals{});
  shared_sort_ = (schedule_workers > 0 ? schedule_workers : workers) >= kSharedSortWorkers;
  redo_at_.assign(n / kSamplesPerChunk + 2, 0);
  bytes_ = (3 * n + 2) * sizeof(std::int32_t) + n * (sizeof(FitPoint) + sizeof(Member) + sizeof(std::int16_t)) + n +
           2 * static_cast<std::size_t>(max_disp) * static_cast<std::size_t>(workers + 2) +
           static_cast<std::size_t>(workers) * (sizeof(SupportPriorCounts) + sizeof(Census) + sizeof(PlaneSums) +
                                                sizeof(Residuals)) +
           static_cast<std::size_t>(max_triangles) + (big_.size() + big_points_.size() + redo_at_.size()) * sizeof(int);
}

void SupportPrior::release() {
  prior_ = LargeArray<std::int16_t>{};
  for (LargeArray<std::int32_t>* a : {&parent_, &count_, &order_})
    *a = LargeArray<std::int32_t>{};
  inten_ = LargeArray<std::uint8_t>{};
  members_ = LargeArray<Member>{};
  next_ = LargeArray<std::uint8_t>{};
  fit_ = LargeArray<FitPoint>{};
  s2_ = std::vector<std::uint16_t>{};
  penalty_ = std::vector<std::uint16_t>{};
  worker_counts_ = std::vector<SupportPriorCounts>{};
  big_ = std::vector<std::int32_t>{};
  big_points_ = std::vector<int>{};
  big_census_ = std::vector<Census>{};
  big_sums_ = std::vector<PlaneSums>{};
  big_residuals_ = std::vector<Residuals>{};
  redo_at_ = std::vector<std::int32_t>{};
  n_big_ = 0;
  bytes_ = 0;
  max_disp_ = 0;
}

// Path halving: each sample on the way points at its grandparent.
int SupportPrior::find(int a) {
  std::int32_t* parent = parent_.get();
  std::int32_t p = load(parent + a);
  while (p != a) {
    const std::int32_t g = load(parent + p);
    store(parent + a, g);
    a = g;
    p = load(parent + a);
  }
  return a;
}

// The larger root goes under the smaller, only while it is still a root (a
// compare-and-swap when other workers join too; alone, a plain store, a
// fifth of the joins' time): the partition and its roots, each segment's
// smallest sample, do not depend on the order of the unions nor on the
// workers.
void SupportPrior::unite(int a, int b, bool shared) {
  std::int32_t* parent = parent_.get();
  if (!shared) {
    // Alone: Rem's union with splicing, which walks both paths at once
    // (the partition and the roots are those of two finds and a link, a
    // little faster).
    std::int32_t x = a, y = b;
    while (rem_step(parent, &x, &y)) {
    }
    return;
  }
  for (;;) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (a < b) std::swap(a, b);
    std::int32_t expected = a;
    if (__atomic_compare_exchange_n(parent + a, &expected, b, false, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) return;
  }
}

void SupportPrior::planes(const StereoParams& params, const SampleLayout& samples, const std::int16_t* disp,
                          int tau, int joined, int next, ThreadPool* pool, FrameTrace* trace) {
  const int n = n_;
  const SupportPriorParams& pp = params.prior;
  std::int32_t* parent = parent_.get();
  Member* members = members_.get();
  // Segments: the components of the mesh edges with |dI| <= tau; each one's
  // root is its smallest sample. joined >= 0: parent holds the segments of
  // that smaller threshold (a finer partition), so only the edges with
  // joined < |dI| <= tau remain; then every sample points at its root.
  if (joined < 0)
    for_chunks(pool, nullptr, TraceKind::kPriorRoots, tau, n, kSamplesPerChunk, [&](int, int i0, int i1) {
      for (int i = i0; i < i1; ++i) parent[i] = i;
    });
  // The mesh edges with joined < |dI| <= tau, each once: the mesh is
  // conforming and its triangles turn one way, so an inner edge comes as
  // (a, b) from one triangle and (b, a) from the other, and (a, b) with
  // a < b is taken. A border edge has one triangle, and the frame's sides are
  // cut exactly at their samples: the pairs of samples next to each other
  // along a side are joined in a last chunk (twice changes nothing in the
  // union-find). The edges are read from the triangles at each level rather
  // than listed once: a list of every edge would be the largest buffer here.
  const Mesh& mesh = *samples.mesh;
  const int n_tri = static_cast<int>(mesh.triangles.size());
  const int tri_chunks = (n_tri + kTrianglesPerChunk - 1) / kTrianglesPerChunk;
  const bool shared = pool != nullptr && pool->size() > 1 && tri_chunks > 0;
  const std::uint8_t* inten = inten_.get();
  std::uint8_t* edge_bits = next_.get();
  const auto join = [&, inten, tau, joined](int a, int b) {
    const int di = std::abs(inten[a] - inten[b]);
    if (di <= tau && di > joined) unite(a, b, shared);
  };
  for_chunks(pool, trace, TraceKind::kPriorJoins, tau, tri_chunks + 1, 1, [&](int, int c0, int c1) {
    const Triangle* tris = mesh.triangles.data();
    for (int c = c0; c < c1; ++c) {
      if (c == tri_chunks) {  // the border
        const int w = samples.width, h = samples.height;
        for (int y : {0, h - 1})  // along the top and bottom rows
          for (int i = samples.row_begin(y); i + 1 < samples.row_begin(y + 1); ++i) join(i, i + 1);
        int prev_left = -1, prev_right = -1;  // along the left and right columns
        for (int y = 0; y < h; ++y) {
          const int first = samples.row_begin(y), last = samples.row_begin(y + 1) - 1;
          if (last < first) continue;
          if (samples.x_of(first) == 0) {
            if (prev_left >= 0) join(prev_left, first);
            prev_left = first;
          }
          if (samples.x_of(last) == w - 1) {
            if (prev_right >= 0) join(prev_right, last);
            prev_right = last;
          }
        }
        continue;
      }
      // A block of triangles at a time: the bits of the edges this level
      // joins (from the previous level, or tested here, marking the next
      // level's on the way), then the list of those edges, each appended
      // whether taken or not and kept by the count (an edge is taken or not
      // about at random: a branch per edge mispredicts often), then the
      // joins in one loop.
      constexpr int kBlock = 256;
      std::uint8_t bits[kBlock];
      std::int32_t from[3 * kBlock], to[3 * kBlock];
      const Triangle* tris_c = tris;
      const std::uint8_t* in = inten;
      std::uint8_t* marks = edge_bits;
      const bool first_level = joined < 0, mark_next = next >= 0;
      const auto within = [](int a, int b, int ia, int ib, unsigned lo, unsigned span) {
        return static_cast<unsigned>((a < b) & (static_cast<unsigned>(std::abs(ia - ib)) - lo < span));
      };
      const unsigned span = static_cast<unsigned>(tau + 1);
      const unsigned next_lo = static_cast<unsigned>(tau + 1), next_span = static_cast<unsigned>(next - tau);
      const int t0 = c * kTrianglesPerChunk, t1 = std::min(n_tri, t0 + kTrianglesPerChunk);
      for (int b0 = t0; b0 < t1; b0 += kBlock) {
        const int nb = std::min(t1 - b0, kBlock);
        if (!first_level) {
          std::copy_n(marks + b0, nb, bits);
        } else {
          for (int j = 0; j < nb; ++j) {
            const Triangle& t = tris_c[b0 + j];
            const int a = t[0], b = t[1], cc = t[2];
            const int ia = in[a], ib = in[b], ic = in[cc];
            if (mark_next)
              marks[b0 + j] = static_cast<std::uint8_t>(within(a, b, ia, ib, next_lo, next_span) |
                                                        within(b, cc, ib, ic, next_lo, next_span) << 1 |
                                                        within(cc, a, ic, ia, next_lo, next_span) << 2);
            bits[j] = static_cast<std::uint8_t>(within(a, b, ia, ib, 0, span) | within(b, cc, ib, ic, 0, span) << 1 |
                                                within(cc, a, ic, ia, 0, span) << 2);
          }
        }
        int m = 0;
        for (int j = 0; j < nb; ++j) {
          const unsigned e = bits[j];
          const Triangle& t = tris_c[b0 + j];
          const int a = t[0], b = t[1], cc = t[2];
          from[m] = a, to[m] = b, m += static_cast<int>(e & 1u);
          from[m] = b, to[m] = cc, m += static_cast<int>(e >> 1 & 1u);
          from[m] = cc, to[m] = a, m += static_cast<int>(e >> 2);
        }
        if (shared) {
          for (int e = 0; e < m; ++e) unite(from[e], to[e], true);
          continue;
        }
        // Alone: the unions a step of Rem's splicing at a time, the unions
        // that go on listed in place for the next round (no branch per
        // step). Unions commute, so the partition and the roots are the same.
        std::int32_t* par = parent;
        while (m > 0) {
          int rest = 0;
          for (int e = 0; e < m; ++e) {
            std::int32_t a = from[e], b = to[e];
            const bool more = rem_step(par, &a, &b);
            from[rest] = a, to[rest] = b, rest += static_cast<int>(more);
          }
          m = rest;
        }
      }
    }
  });
  // Members grouped by segment (a counting sort by root). The sizes go to
  // count[r + 2], their running sum makes count[r + 1] the segment's first
  // slot, and placing the members moves it past the last: then count[r] is
  // the segment's first slot and count[r + 1] its end. The segments of at
  // least kBigSegment samples are listed apart: one of them (a road, a
  // wall) can take more than all the others of its level together, so its
  // own passes are shared by the workers. Shared, the sizes are counted and
  // the slots taken by atomic adds, one per run of consecutive samples of a
  // segment: a segment's members then come in any order, and every step
  // after is a sum, an OR or a write per member, the same in any order.
  std::int32_t* count = count_.get();
  std::int32_t* order = order_.get();
  const bool shared_sort = shared_sort_;
  std::fill_n(count, n + 2, 0);
  // Every sample pointed at its root. A parent is at most its sample, so
  // in ascending order a parent inside the chunk already points at its root;
  // one before the chunk may be another worker's, and is followed.
  for_chunks(pool, trace, TraceKind::kPriorRoots, tau, n, kSamplesPerChunk, [&](int, int i0, int i1) {
    if (!shared_sort) {
      for (int i = i0; i < i1; ++i) {
        const std::int32_t p = load(parent + i);
        store(parent + i, p >= i0 ? load(parent + p) : find(p));
      }
      return;
    }
    std::int32_t run_root = -1, run = 0;
    for (int i = i0; i < i1; ++i) {
      const std::int32_t p = load(parent + i);
      const std::int32_t r = p >= i0 ? load(parent + p) : find(p);
      store(parent + i, r);
      if (r != run_root) {
        if (run > 0) __atomic_fetch_add(count + run_root + 2, run, __ATOMIC_RELAXED);
        run_root = r;
        run = 0;
      }
      ++run;
    }
    if (run > 0) __atomic_fetch_add(count + run_root + 2, run, __ATOMIC_RELAXED);
  });
  if (!shared_sort)
    for (int i = 0; i < n; ++i) ++count[parent[i] + 2];
  n_big_ = 0;
  for (int r = 0; r < n; ++r) {
    if (count[r + 2] >= kBigSegment) big_[static_cast<std::size_t>(n_big_++)] = r;
    count[r + 2] += count[r + 1];
  }
  if (!shared_sort) {
    for (int i = 0; i < n; ++i) order[count[parent[i] + 1]++] = i;
  } else {
    for_chunks(pool, trace, TraceKind::kPriorRoots, tau, n, kSamplesPerChunk, [&](int, int i0, int i1) {
      const auto place = [&](std::int32_t r, int first, int end) {
        const std::int32_t at = __atomic_fetch_add(count + r + 1, end - first, __ATOMIC_RELAXED);
        for (int k = first; k < end; ++k) order[at + (k - first)] = k;
      };
      std::int32_t run_root = parent[i0];
      int run_first = i0;
      for (int i = i0; i < i1; ++i) {
        const std::int32_t r = parent[i];
        if (r == run_root) continue;
        place(run_root, run_first, i);
        run_root = r;
        run_first = i;
      }
      place(run_root, run_first, i1);
    });
  }
  const std::int64_t tol = pp.plane_tol_q4;
  const int lo = kDispOne * params.d_min, hi = kDispOne * (params.d_min + params.num_disp - 1);
  FitPoint* fit_points = fit_.get();
  std::int16_t* prior = prior_.get();
  // The steps of a segment's plane over members [g0, g1) of order, each
  // writing only its own members' values and slots of fit_.
  // gather: the support points of members [g0, g1) to fit_[g0 ..] (returns
  // how many); also sets *other when a member is neither support nor covered.
  const auto gather = [&](int g0, int g1, bool* other) {
    FitPoint* pts = fit_points + g0;
    int np = 0;
    bool any_other = false;
    for (int j = g0; j < g1; ++j) {
      const Member m = members[order[j]];
      if (m.flags & kSupport)
        pts[np++] = FitPoint{m.x, m.y, m.d};
      else
        any_other = any_other || !(m.flags & kCovered);
    }
    *other = *other || any_other;
    return np;
  };
  // Fit 0 on every support point, fits 1..3 on those within 2 tol of the previous plane.
  const auto add_points = [&](const FitPoint* pts, int np, int fit, const IntPlane& plane, PlaneSums* sums) {
    if (fit == 0) {
      for (int j = 0; j < np; ++j) sums->add(pts[j].x, pts[j].y, pts[j].d);
      return;
    }
    const std::int64_t low = -512 * tol, high = 256 * (2 * tol + 1);  // |at - d| <= 2 tol
    for (int j = 0; j < np; ++j) {
      const FitPoint p = pts[j];
      const std::int64_t t = plane.residual_q8(p.x, p.y, p.d);
      if (t >= low && t < high) sums->add(p.x, p.y, p.d);
    }
  };
  const auto next_plane = [&](const PlaneSums& sums, IntPlane* plane) {
    if (sums.n < 3) return false;
    IntPlane np;
    np.xbar = static_cast<int>(floor_div(sums.sx, sums.n));
    np.ybar = static_cast<int>(floor_div(sums.sy, sums.n));
    np.dbar = static_cast<int>(floor_div(sums.sd, sums.n));
    if (!solve_plane(sums.moments(np.xbar, np.ybar, np.dbar), sums.n, &np)) return false;
    *plane = np;
    return true;
  };
  // Accepted when at least half the support lies within tol and the
  // residuals, each capped at 2 tol, have a mean square of at most tol^2.
  const auto residuals = [&](const FitPoint* pts, int np, const IntPlane& plane, Residuals* res) {
    for (int j = 0; j < np; ++j) {
      const FitPoint p = pts[j];
      const std::int64_t e = abs64(plane.at(p.x, p.y) - p.d);
      if (e <= tol) ++res->inliers;
      res->sq += std::min(e * e, 4 * tol * tol);
    }
  };
  const auto accepted = [&](const Residuals& res, int support) {
    return 2 * res.inliers >= support && res.sq <= tol * tol * support;
  };
  const auto cover = [&](int g0, int g1, const IntPlane& plane) {
    for (int j = g0; j < g1; ++j) {
      const int i = order[j];
      Member& m = members[i];
      if (m.flags & (kSupport | kCovered)) continue;
      m.flags |= kCovered;
      prior[i] = static_cast<std::int16_t>(std::clamp(plane.at(m.x, m.y), lo, hi));
    }
  };
  // Segment r on one worker: true when it gets a plane.
  const auto fit_segment = [&](int r) {
    const int g0 = count[r], g1 = count[r + 1];
    if (g1 - g0 < 2 || g1 - g0 >= kBigSegment) return false;  // a plane needs support and another sample
    // The census and the support points in one pass over the members.
    const FitPoint* pts = fit_points + g0;
    bool other = false;
    const int np = gather(g0, g1, &other);
    if (!other || np < pp.plane_min) return false;
    IntPlane plane;
    PlaneSums last;
    for (int fit = 0; fit < 4; ++fit) {
      PlaneSums sums;
      add_points(pts, np, fit, plane, &sums);
      // The plane is a function of the sums: the same sums as the fit
      // before give its plane again, and so every later fit.
      if (fit > 0 && sums == last) break;
      if (!next_plane(sums, &plane)) return false;
      last = sums;
    }
    Residuals res;
    residuals(pts, np, plane, &res);
    if (!accepted(res, np)) return false;
    cover(g0, g1, plane);
    return true;
  };
  for_chunks(pool, trace, TraceKind::kPriorSegments, tau, n, kRootsPerChunk, [&](int w, int r0, int r1) {
    for (int r = r0; r < r1; ++r) worker_counts_[static_cast<std::size_t>(w)].planes += fit_segment(r) ? 1 : 0;
  });
  // The big segments, one after another, each step in chunks of members:
  // every chunk gathers its support points to its own slots, and the sums
  // of the chunks are added per worker, then together (integer sums: the
  // same in any order).
  for (int b = 0; b < n_big_; ++b) {
    const int r = big_[static_cast<std::size_t>(b)];
    const int g0 = count[r], g1 = count[r + 1], members = g1 - g0;
    const int chunks = (members + kBigChunk - 1) / kBigChunk;
    const auto chunk_begin = [&](int c) { return g0 + c * kBigChunk; };
    const auto chunk_end = [&](int c) { return std::min(g1, g0 + (c + 1) * kBigChunk); };
    for (Census& c : big_census_) c = Census{};
    for_chunks(pool, trace, TraceKind::kPriorSegments, tau, chunks, 1, [&](int w, int c0, int c1) {
      for (int c = c0; c < c1; ++c) {
        Census& wc = big_census_[static_cast<std::size_t>(w)];
        const int np = gather(chunk_begin(c), chunk_end(c), &wc.other);
        big_points_[static_cast<std::size_t>(c)] = np;
        wc.support += np;
      }
    });
    Census all;
    for (const Census& c : big_census_) {
      all.support += c.support;
      all.other = all.other || c.other;
    }
    if (!all.other || all.support < pp.plane_min) continue;
    IntPlane plane;
    PlaneSums last;
    bool ok = true;
    for (int fit = 0; fit < 4 && ok; ++fit) {
      for (PlaneSums& s : big_sums_) s = PlaneSums{};
      for_chunks(pool, trace, TraceKind::kPriorSegments, tau, chunks, 1, [&](int w, int c0, int c1) {
        for (int c = c0; c < c1; ++c)
          add_points(fit_points + chunk_begin(c), big_points_[static_cast<std::size_t>(c)], fit, plane,
                     &big_sums_[static_cast<std::size_t>(w)]);
      });
      PlaneSums sums;
      for (const PlaneSums& s : big_sums_) sums.merge(s);
      if (fit > 0 && sums == last) break;  // converged (as in fit_segment)
      ok = next_plane(sums, &plane);
      last = sums;
    }
    if (!ok) continue;
    for (Residuals& res : big_residuals_) res = Residuals{};
    for_chunks(pool, trace, TraceKind::kPriorSegments, tau, chunks, 1, [&](int w, int c0, int c1) {
      for (int c = c0; c < c1; ++c)
        residuals(fit_points + chunk_begin(c), big_points_[static_cast<std::size_t>(c)], plane,
                  &big_residuals_[static_cast<std::size_t>(w)]);
    });
    Residuals res;
    for (const Residuals& x : big_residuals_) {
      res.inliers += x.inliers;
      res.sq += x.sq;
    }
    if (!accepted(res, all.support)) continue;
    for_chunks(pool, trace, TraceKind::kPriorSegments, tau, chunks, 1, [&](int, int c0, int c1) {
      for (int c = c0; c < c1; ++c) cover(chunk_begin(c), chunk_end(c), plane);
    });
    ++worker_counts_[0].planes;
  }
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
    // Here, in the same chunks: a one-worker trace shows the items that
    // more workers would share (the scaling model replays them).
    for (int j0 = 0; j0 < n; j0 += chunk) traced(0, j0, std::min(n, j0 + chunk));
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
  Member* members = members_.get();
  const std::int16_t* prior = prior_.get();
  std::int32_t* pending = order_.get();  // the list of samples decided again (the segments are done with order_)
  for (SupportPriorCounts& c : worker_counts_) c = SupportPriorCounts{};
  // (Locals in the loops: their byte stores may alias anything the lambda
  // captured, which it would load again for every sample.)
  for_chunks(pool, trace, TraceKind::kPriorSetup, 0, n, kSamplesPerChunk, [&](int w, int i0, int i1) {
    const Vertex* v = mesh.vertices.data();
    const std::uint8_t* image = left.data;
    const std::ptrdiff_t stride = left.stride_bytes;  // u8 pixels: bytes
    const int min_conf = pp.support_conf;
    std::uint8_t* in = inten;
    Member* mem = members;
    const std::int16_t* dq = disp;
    const std::uint8_t* cf = conf;
    int support = 0;
    for (int i = i0; i < i1; ++i) {
      in[i] = image[v[i].y * stride + v[i].x];
      const bool s = dq[i] != kInvalidDispQ4 && cf[i] >= min_conf;
      mem[i] = Member{static_cast<std::int16_t>(v[i].x), static_cast<std::int16_t>(v[i].y), dq[i],
                      static_cast<std::uint8_t>(s ? kSupport : 0)};
      support += s ? 1 : 0;
    }
    worker_counts_[static_cast<std::size_t>(w)].support += support;
  });
  // Planes: the fine level, then the coarse one for samples still uncovered.
  const bool nested = pp.seg_fine > 0 && pp.seg_coarse >= pp.seg_fine;  // the coarse level adds edges to the fine one's
  if (pp.seg_fine > 0) planes(params, samples, disp, pp.seg_fine, -1, nested ? pp.seg_coarse : -1, pool, trace);
  if (pp.seg_coarse > 0) planes(params, samples, disp, pp.seg_coarse, nested ? pp.seg_fine : -1, -1, pool, trace);
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
  // (Shared: each chunk of samples counts its own, then lists them at its
  // place, in the same order.)
  int n_redo = 0;
  if (!shared_sort_) {
    for (int i = 0; i < n; ++i)
      if (members[i].flags & kCovered) pending[n_redo++] = i;
  } else {
    std::int32_t* at = redo_at_.data();
    for_chunks(pool, trace, TraceKind::kPriorSetup, 1, n, kSamplesPerChunk, [&](int, int i0, int i1) {
      std::int32_t k = 0;
      for (int i = i0; i < i1; ++i) k += (members[i].flags & kCovered) ? 1 : 0;
      at[i0 / kSamplesPerChunk] = k;
    });
    const int chunks = (n + kSamplesPerChunk - 1) / kSamplesPerChunk;
    for (int c = 0; c < chunks; ++c) {
      const std::int32_t k = at[c];
      at[c] = n_redo;
      n_redo += k;
    }
    for_chunks(pool, trace, TraceKind::kPriorSetup, 1, n, kSamplesPerChunk, [&](int, int i0, int i1) {
      std::int32_t j = at[i0 / kSamplesPerChunk];
      for (int i = i0; i < i1; ++i)
        if (members[i].flags & kCovered) pending[j++] = i;
    });
  }
  constexpr int kAhead = 8;
  const std::size_t row_bytes = static_cast<std::size_t>(d) * sizeof(std::uint16_t);
  for_chunks(pool, trace, TraceKind::kPriorSamples, 0, n_redo, kRedoPerChunk, [&](int w, int j0, int j1) {
    std::uint16_t* s2 = s2_.data() + static_cast<std::size_t>(w) * static_cast<std::size_t>(max_disp_);
    SupportPriorCounts& wc = worker_counts_[static_cast<std::size_t>(w)];
    for (int j = j0; j < j1; ++j) {
      if (j + kAhead < j1) {
        prefetch_lines<0>(pm.summed_costs_row(pending[j + kAhead]), row_bytes);
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
      const bool was_valid = disp[i] != kInvalidDispQ4;
      if (pp.uniqueness_pct > 0 && any_rival &&
          std::uint64_t{rival} * 100u <= std::uint64_t{best} * static_cast<std::uint64_t>(100 + pp.uniqueness_pct)) {
        disp[i] = kInvalidDispQ4;
        ++wc.rejected;
        wc.lost += was_valid ? 1 : 0;
        continue;
      }
      wc.recovered += was_valid ? 0 : 1;
      // The sub-pixel value: the plane's, when it lies within half a pixel
      // of the new winner (the penalty's kink at kp would pull a fit through
      // S' towards the whole disparity), else the fit through S'.
      const int whole = kDispOne * (dmin + k);
      int off = 0;
      if (params.dp.subpixel && std::abs(prior[i] - whole) <= kDispOne / 2)
        off = prior[i] - whole;
      else if (params.dp.subpixel && k > 0 && k < d - 1)
        off = subpixel_offset_q4(params.dp.subpixel_fit, static_cast<int>(exact(k - 1)), static_cast<int>(best),
                                 static_cast<int>(exact(k + 1)));
      disp[i] = static_cast<std::int16_t>(whole + off);
      // The confidence is the data's, not the prior's: section 7's formula on
      // S at the new winner, against S's smallest value two or more steps away
      // (the lowest measured one when that is not above S(k')); below the
      // support. (From S' the prior's penalty would widen every margin, and
      // --min-confidence would keep samples the data do not single out.)
      // Whatever S's own winner, that value is S's minimum over |k - k'| > 1.
      const std::uint16_t data_rival = ks.min_outside_u16(s, d, k);
      const int data_conf = data_rival > s[k] ? measured_confidence(s[k], data_rival) : kMinMeasuredConfidence;
      conf[i] = static_cast<std::uint8_t>(std::min(conf_cap, data_conf));
    }
  });
  for (const SupportPriorCounts& c : worker_counts_) {
    counts.support += c.support;
    counts.recovered += c.recovered;
    counts.lost += c.lost;
    counts.redecided += c.redecided;
    counts.rejected += c.rejected;
    counts.planes += c.planes;
  }
  return counts;
}

}  // namespace tristereo
