#include "src/fill/sample_fill.hpp"

#include <algorithm>
#include <climits>

#include "platform/thread_pool.hpp"
#include "tristereo/fixed_point.hpp"

namespace tristereo {

namespace {
// Pending samples per chunk of a round: a chunk costs microseconds.
constexpr int kPendingPerChunk = 2048;

template <class T>
LargeArray<T> untouched(std::size_t n) {
  return large_array<T>(n);
}
}  // namespace

void SampleFill::configure(int max_samples, int max_triangles) {
  max_samples_ = max_samples;
  max_triangles_ = max_triangles;
  const auto n = static_cast<std::size_t>(max_samples);
  offsets_ = untouched<std::int32_t>(n + 1);
  neighbours_ = untouched<std::int32_t>(static_cast<std::size_t>(max_triangles) * 6);
  pending_ = untouched<std::int32_t>(n);
  candidate_ = untouched<std::int32_t>(n);
}

// CSR of the mesh's undirected edges, each stored once per triangle side (an
// interior edge twice: harmless under min).
void SampleFill::build_adjacency(const SampleLayout& samples) {
  const int n = samples.count();
  std::int32_t* off = offsets_.get();
  std::fill(off, off + n + 1, 0);
  for (const Triangle& t : samples.mesh->triangles)
    for (int e = 0; e < 3; ++e) off[t[static_cast<std::size_t>(e)] + 1] += 2;
  for (int i = 0; i < n; ++i) off[i + 1] += off[i];
  std::int32_t* fill_at = candidate_.get();  // reused as insertion cursors
  std::copy(off, off + n, fill_at);
  for (const Triangle& t : samples.mesh->triangles)
    for (int e = 0; e < 3; ++e) {
      const int a = t[static_cast<std::size_t>(e)];
      neighbours_[static_cast<std::size_t>(fill_at[a]++)] = t[static_cast<std::size_t>((e + 1) % 3)];
      neighbours_[static_cast<std::size_t>(fill_at[a]++)] = t[static_cast<std::size_t>((e + 2) % 3)];
    }
}

void SampleFill::prepare(const SampleLayout& samples) {
  prepared_for_ = nullptr;
  if (samples.dense()) return;
  build_adjacency(samples);
  prepared_for_ = samples.mesh;
}

int SampleFill::fill(const SampleLayout& samples, std::int16_t* disp_q4, ThreadPool* pool) {
  const bool prepared = !samples.dense() && prepared_for_ == samples.mesh;
  prepared_for_ = nullptr;  // one frame's
  const int n = samples.count();
  int pending = 0;
  for (int i = 0; i < n; ++i)
    if (disp_q4[i] == kInvalidDispQ4) pending_[static_cast<std::size_t>(pending++)] = i;
  if (pending == 0) return 0;
  if (!samples.dense() && !prepared) build_adjacency(samples);
  std::int32_t* cand = candidate_.get();
  const int w = samples.width, h = samples.height;
  // Candidates from neighbours valid at the start of the round, for pending[j0, j1).
  const auto candidates = [&](int j0, int j1) {
    for (int j = j0; j < j1; ++j) {
      const int i = pending_[static_cast<std::size_t>(j)];
      int best = INT_MAX;
      auto offer = [&](int q) {
        const int v = disp_q4[q];
        if (v != kInvalidDispQ4 && v < best) best = v;
      };
      if (samples.dense()) {
        const int x = i % w, y = i / w;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int qx = x + dx, qy = y + dy;
            if ((dx != 0 || dy != 0) && qx >= 0 && qx < w && qy >= 0 && qy < h) offer(qy * w + qx);
          }
      } else {
        for (int e = offsets_[static_cast<std::size_t>(i)]; e < offsets_[static_cast<std::size_t>(i) + 1]; ++e)
          offer(neighbours_[static_cast<std::size_t>(e)]);
      }
      cand[j] = best;
    }
  };
  int filled = 0;
  for (;;) {
    if (pool != nullptr && pool->size() > 1 && pending >= 2 * kPendingPerChunk) {
      chunks_.reset(0, pending, kPendingPerChunk);
      pool->run([&](int) {
        int j0 = 0, j1 = 0;
        while (chunks_.next(&j0, &j1)) candidates(j0, j1);
      });
    } else {
      candidates(0, pending);
    }
    // Write after the whole scan, so a round only sees the previous round's
    // values; then keep the samples still unfilled.
    int kept = 0, now = 0;
    for (int j = 0; j < pending; ++j) {
      const int i = pending_[static_cast<std::size_t>(j)];
      if (cand[j] != INT_MAX) {
        disp_q4[i] = static_cast<std::int16_t>(cand[j]);
        ++now;
      } else {
        pending_[static_cast<std::size_t>(kept++)] = i;
      }
    }
    filled += now;
    pending = kept;
    if (now == 0 || pending == 0) break;
  }
  return filled;
}

}  // namespace tristereo
