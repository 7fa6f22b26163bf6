#include "src/fill/sample_fill.hpp"

#include <algorithm>
#include <climits>
#include <cstring>

#include "platform/clock.hpp"
#include "platform/thread_pool.hpp"
#include "src/select/confidence.hpp"
#include "tristereo/fixed_point.hpp"

namespace tristereo {

namespace {
// Pending samples per chunk of a round: a chunk costs microseconds.
constexpr int kPendingPerChunk = 2048;
// Samples per chunk of the scan for the invalid ones.
constexpr int kScanPerChunk = 16384;
// Triangles per chunk of a mesh fill's first walk (the one over all of
// them: 8192 cost about 35 us on a KITTI frame, so two workers finish
// within one chunk of each other), and of the later rounds' walks over the
// triangles still live.
constexpr int kTrianglesPerChunk = 8192;
constexpr int kLiveTrianglesPerChunk = 4096;



template <class T>
LargeArray<T> untouched(std::size_t n) {
  return large_array<T>(n);
}
// The end of a round for pending[j0, j1): writes each pending sample's
// candidate (cand_of(j, i) for pending[j] = sample i, INT_MAX for none) after
// the round's whole walk, so a round only sees the previous round's values;
// keeps the samples still unfilled in pending[j0, j0 + kept) and returns
// kept. `confidence` (optional) gets round `round`'s filled_confidence().
template <class CandOf>
int write_round(std::int32_t* pending, int j0, int j1, std::int16_t* disp_q4, std::uint8_t* confidence,
                int round, CandOf cand_of) {
  const std::uint8_t c = filled_confidence(round);
  int kept = j0;
  for (int j = j0; j < j1; ++j) {
    const int i = pending[j];
    const int v = cand_of(j, i);
    if (v != INT_MAX) {
      disp_q4[i] = static_cast<std::int16_t>(v);
      if (confidence != nullptr) confidence[i] = c;
    } else {
      pending[kept++] = i;
    }
  }
  return kept - j0;
}

}  // namespace

void SampleFill::configure(int max_samples, int max_triangles, int workers) {
  max_samples_ = max_samples;
  max_triangles_ = max_triangles;
  const auto n = static_cast<std::size_t>(max_samples);
  pending_ = untouched<std::int32_t>(n);
  candidate_ = untouched<std::int32_t>(n);
  worker_candidate_.clear();
  for (int w = 1; w < workers; ++w) worker_candidate_.push_back(untouched<std::int32_t>(n));
  live_ = untouched<std::int32_t>(static_cast<std::size_t>(max_triangles));
  chunk_live_.assign(static_cast<std::size_t>(max_triangles / std::min(kTrianglesPerChunk, kLiveTrianglesPerChunk) + 1), 0);
  chunk_kept_.assign(static_cast<std::size_t>(max_samples / std::min(kScanPerChunk, kPendingPerChunk) + 1), 0);
}

int SampleFill::mesh_workers(const ThreadPool* pool) const {
  return pool != nullptr ? std::min(pool->size(), static_cast<int>(worker_candidate_.size()) + 1) : 1;
}

template <class Body>
int SampleFill::compacting(ThreadPool* pool, int n, int chunk, Body body) {
  std::int32_t* out = pending_.get();
  const int chunks = (n + chunk - 1) / chunk;
  if (pool == nullptr || pool->size() < 2 || chunks < 2) {
    const std::int64_t t0 = trace_ != nullptr ? monotonic_ns() : 0;
    const int kept = body(0, n);
    if (trace_ != nullptr) trace_->record(0, TraceKind::kFillChunk, t0, monotonic_ns(), 0, n, chunk);
    return kept;
  }
  chunks_.reset(0, chunks, 1);
  pool->run([&](int w) {
    int c0 = 0, c1 = 0;
    while (chunks_.next(&c0, &c1)) {
      const int j0 = c0 * chunk, j1 = std::min(n, j0 + chunk);
      const std::int64_t t0 = trace_ != nullptr ? monotonic_ns() : 0;
      chunk_kept_[static_cast<std::size_t>(c0)] = body(j0, j1);
      if (trace_ != nullptr) trace_->record(w, TraceKind::kFillChunk, t0, monotonic_ns(), j0, j1, chunk);
    }
  });
  // What each chunk kept, joined up in order (the first chunk's is in place).
  int kept = chunk_kept_[0];
  for (int c = 1; c < chunks; ++c) {
    const int k = chunk_kept_[static_cast<std::size_t>(c)];
    std::memmove(out + kept, out + static_cast<std::ptrdiff_t>(c) * chunk, static_cast<std::size_t>(k) * sizeof(*out));
    kept += k;
  }
  return kept;
}

int SampleFill::fill(const SampleLayout& samples, std::int16_t* disp_q4, ThreadPool* pool,
                     std::uint8_t* confidence) {
  const int n = samples.count();
  // Without a branch on the data: a quarter of the samples or so are
  // invalid, spread out, and the branch mispredicted at every other one.
  std::int32_t* pending_ids = pending_.get();
  const int pending = compacting(pool, n, kScanPerChunk, [&](int i0, int i1) {
    int k = i0;
    for (int i = i0; i < i1; ++i) {
      pending_ids[k] = i;
      k += disp_q4[i] == kInvalidDispQ4 ? 1 : 0;
    }
    return k - i0;
  });
  if (pending == 0) return 0;
  return samples.dense() ? fill_grid(samples, disp_q4, pool, pending, confidence)
                         : fill_mesh(samples, disp_q4, pool, pending, confidence);
}

int SampleFill::fill_grid(const SampleLayout& samples, std::int16_t* disp_q4, ThreadPool* pool, int pending,
                          std::uint8_t* confidence) {
  std::int32_t* cand = candidate_.get();
  const int w = samples.width, h = samples.height;
  // Candidates from the 8 neighbours valid at the start of the round, for pending[j0, j1).
  const auto candidates = [&](int j0, int j1) {
    for (int j = j0; j < j1; ++j) {
      const int i = pending_[static_cast<std::size_t>(j)];
      int best = INT_MAX;
      const int x = i % w, y = i / w;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int qx = x + dx, qy = y + dy;
          if ((dx == 0 && dy == 0) || qx < 0 || qx >= w || qy < 0 || qy >= h) continue;
          const int v = disp_q4[qy * w + qx];
          if (v != kInvalidDispQ4 && v < best) best = v;
        }
      cand[j] = best;
    }
  };
  int filled = 0;
  for (int round = 1;; ++round) {
    if (pool != nullptr && pool->size() > 1 && pending >= 2 * kPendingPerChunk) {
      chunks_.reset(0, pending, kPendingPerChunk);
      pool->run([&](int wk) {
        int j0 = 0, j1 = 0;
        while (chunks_.next(&j0, &j1)) {
          const std::int64_t t0 = trace_ != nullptr ? monotonic_ns() : 0;
          candidates(j0, j1);
          if (trace_ != nullptr) trace_->record(wk, TraceKind::kFillChunk, t0, monotonic_ns(), j0, j1, kPendingPerChunk);
        }
      });
    } else if (trace_ == nullptr) {
      candidates(0, pending);
    } else {  // one item (c: the chunk a pool would take)
      const std::int64_t t0 = monotonic_ns();
      candidates(0, pending);
      trace_->record(0, TraceKind::kFillChunk, t0, monotonic_ns(), 0, pending, kPendingPerChunk);
    }
    const int kept = compacting(pool, pending, kPendingPerChunk, [&](int j0, int j1) {
      return write_round(pending_.get(), j0, j1, disp_q4, confidence, round, [cand](int j, int) { return cand[j]; });
    });
    const int now = pending - kept;
    pending = kept;
    filled += now;
    if (now == 0 || pending == 0) break;
  }
  return filled;
}

int SampleFill::fill_mesh(const SampleLayout& samples, std::int16_t* disp_q4, ThreadPool* pool, int pending,
                          std::uint8_t* confidence) {
  const Triangle* tris = samples.mesh->triangles.data();
  const auto n_tris = static_cast<std::int32_t>(samples.mesh->triangles.size());
  std::int32_t* live = live_.get();
  std::int32_t* cand = candidate_.get();  // set to INT_MAX by the first walk, as every worker's
  // Offers along triangle t's edges to its corners invalid at the start of the
  // round. True when t must be walked again: only when all three corners are
  // invalid. With one or two valid corners, every invalid one takes an offer
  // from t, so all three are valid after this round and t can never carry a
  // value again (the first round keeps a few percent of the triangles, not
  // the quarter to a third that have an invalid corner).
  const auto walk = [&](std::int32_t t, auto offer) {
    const Triangle& tr = tris[t];
    const int a = tr[0], b = tr[1], c = tr[2];
    const int da = disp_q4[a], db = disp_q4[b], dc = disp_q4[c];
    const bool ia = da == kInvalidDispQ4, ib = db == kInvalidDispQ4, ic = dc == kInvalidDispQ4;
    if (!(ia || ib || ic)) return false;
    if (ia && ib && ic) return true;
    const int va = ia ? INT_MAX : da, vb = ib ? INT_MAX : db, vc = ic ? INT_MAX : dc;
    if (ia) offer(a, std::min(vb, vc));
    if (ib) offer(b, std::min(va, vc));
    if (ic) offer(c, std::min(va, vb));
    return false;
  };
  const auto offer_alone = [cand](int i, int v) {
    if (v < cand[i]) cand[i] = v;
  };
  // One round's walk over n triangles (live[0, n) when `listed`, else all of
  // them); keeps those walk() keeps in live[0, kept). With a pool and enough
  // triangles, by chunks: each chunk keeps its triangles in place in its own
  // stretch of live_, joined up after; each worker offers into its own
  // candidates, and the round's end takes the smallest of them (a corner can
  // be in two workers' chunks; an atomic min per offer cost more than the
  // walk it shared). A sample still pending has INT_MAX in every worker's
  // array (it took no offer anywhere), so the arrays are set once a frame,
  // before the first walk, each by the worker that offers into it: set by
  // the scan's chunks, half of each array's lines were in the other core's
  // cache, and the first walk took as long on each of two workers as on one.
  const int workers = mesh_workers(pool);
  const int n_samples = samples.count();
  bool shared_walks = false;  // a walk ran on the pool: every worker's array is in use
  const auto walk_round = [&](bool listed, int n, int chunk) {
    const int chunks = (n + chunk - 1) / chunk;
    if (workers < 2 || chunks < 2) {
      if (!listed) std::fill_n(cand, n_samples, INT_MAX);
      int kept = 0;
      for (int j = 0; j < n; ++j) {
        const std::int32_t t = listed ? live[j] : j;
        if (walk(t, offer_alone)) live[kept++] = t;
      }
      return kept;
    }
    // Each worker's home: the chunks it most likely decided (two workers:
    // worker 0's forward pass decides the bottom half of the rows, worker 1's
    // backward pass the top half; the triangles come in rows of tiles), so
    // the disparities it reads are in its own core's caches.
    homes_.reset(chunks, workers);
    pool->run([&](int w) {
      if (w >= workers) return;
      std::int32_t* own = w == 0 ? cand : worker_candidate_[static_cast<std::size_t>(w - 1)].get();
      if (!shared_walks) {  // the first walk on the pool (cand may hold no-offers already: harmless)
        const std::int64_t t0 = trace_ != nullptr ? monotonic_ns() : 0;
        std::fill_n(own, n_samples, INT_MAX);
        if (trace_ != nullptr) trace_->record(w, TraceKind::kFillChunk, t0, monotonic_ns(), 0, n_samples, 0);
      }
      const auto offer_own = [own](int i, int v) {
        if (v < own[i]) own[i] = v;
      };
      int c0 = 0;
      while (homes_.next(workers - 1 - w, &c0)) {
        const int j0 = c0 * chunk, j1 = std::min(n, j0 + chunk);
        const std::int64_t t0 = trace_ != nullptr ? monotonic_ns() : 0;
        int kept = j0;
        for (int j = j0; j < j1; ++j) {
          const std::int32_t t = listed ? live[j] : j;
          if (walk(t, offer_own)) live[kept++] = t;
        }
        chunk_live_[static_cast<std::size_t>(c0)] = kept - j0;
        if (trace_ != nullptr) trace_->record(w, TraceKind::kFillChunk, t0, monotonic_ns(), j0, j1, chunk);
      }
    });
    shared_walks = true;
    int kept = 0;
    for (int c = 0; c < chunks; ++c) {
      const std::int32_t* from = live + static_cast<std::ptrdiff_t>(c) * chunk;
      kept = static_cast<int>(std::copy(from, from + chunk_live_[static_cast<std::size_t>(c)], live + kept) - live);
    }
    return kept;
  };
  // The first round walks every triangle; each later one walks what the one
  // before kept.
  // A walk the caller does alone is one trace item (c: the chunk a pool would
  // take); timed here, outside walk_round, whose loops the compiler then
  // still specialises (timing inside it made the one-worker fill 25 % slower).
  const auto traced_round = [&](bool listed, int n, int chunk) {
    const bool alone = workers < 2 || n <= chunk;  // walk_round's test: fewer than two chunks
    const std::int64_t t0 = trace_ != nullptr && alone ? monotonic_ns() : 0;
    const int kept = listed ? walk_round(true, n, chunk) : walk_round(false, n, chunk);
    if (trace_ != nullptr && alone) trace_->record(0, TraceKind::kFillChunk, t0, monotonic_ns(), 0, n, chunk);
    return kept;
  };
  int n_live = trace_ == nullptr ? walk_round(false, n_tris, kTrianglesPerChunk)
                                 : traced_round(false, n_tris, kTrianglesPerChunk);
  int filled = 0;
  for (int round = 1;; ++round) {
    const auto smallest_offer = [&](int, int i) {
      int v = cand[i];
      for (int w = 1; w < (shared_walks ? workers : 1); ++w) v = std::min(v, worker_candidate_[static_cast<std::size_t>(w - 1)][static_cast<std::size_t>(i)]);
      return v;
    };
    const int kept = compacting(pool, pending, kPendingPerChunk, [&](int j0, int j1) {
      return write_round(pending_.get(), j0, j1, disp_q4, confidence, round, smallest_offer);
    });
    const int now = pending - kept;
    pending = kept;
    filled += now;
    if (now == 0 || pending == 0) break;
    n_live = trace_ == nullptr ? walk_round(true, n_live, kLiveTrianglesPerChunk)
                               : traced_round(true, n_live, kLiveTrianglesPerChunk);
  }
  return filled;
}

}  // namespace tristereo
