// Tritree output: the canonical mesh (include/tristereo/mesh.hpp) from the
// leaves, in O(W H + triangles) with the buffers allocated at configure.
#include <algorithm>

#include "platform/thread_pool.hpp"
#include "src/tritree/tritree.hpp"

namespace tristereo {

void Tritree::finish(Mesh& mesh) {
  const int w = gray_.width;
  const int h = gray_.height;
  const std::size_t pixels = static_cast<std::size_t>(w) * h;

  // Vertex ids in raster order: mark the grid, then scan it.
  std::fill(vertex_id_.begin(), vertex_id_.begin() + pixels, -1);
  for (std::int32_t i = 0; i < node_count_; ++i) {
    const Node& n = nodes_[i];
    for (int j = 0; j < 3; ++j) vertex_id_[static_cast<std::size_t>(n.y[j]) * w + n.x[j]] = 0;
  }
  mesh.width = w;
  mesh.height = h;
  mesh.vertices.clear();
  mesh.row_start.resize(static_cast<std::size_t>(h) + 1);
  std::int32_t count = 0;
  for (int y = 0; y < h; ++y) {
    mesh.row_start[y] = count;
    std::int32_t* row = vertex_id_.data() + static_cast<std::size_t>(y) * w;
    for (int x = 0; x < w; ++x) {
      if (row[x] < 0) continue;
      row[x] = count++;
      mesh.vertices.push_back(Vertex{x, y});
    }
  }
  mesh.row_start[h] = count;

  // Triangles: rotate so the smallest id comes first (orientation kept), then
  // counting-sort by that id and finish each bucket (a vertex's fan) with a
  // small sort.
  std::fill(bucket_.begin(), bucket_.begin() + count + 1, 0);
  for (std::int32_t i = 0; i < node_count_; ++i) {
    const Node& n = nodes_[i];
    Triangle t;
    for (int j = 0; j < 3; ++j) t[j] = vertex_id_[static_cast<std::size_t>(n.y[j]) * w + n.x[j]];
    const int r = (t[1] < t[0] && t[1] < t[2]) ? 1 : (t[2] < t[0] && t[2] < t[1]) ? 2 : 0;
    tri_scratch_[i] = Triangle{t[r], t[(r + 1) % 3], t[(r + 2) % 3]};
    ++bucket_[tri_scratch_[i][0] + 1];
  }
  for (std::int32_t v = 0; v < count; ++v) bucket_[v + 1] += bucket_[v];
  mesh.triangles.resize(static_cast<std::size_t>(node_count_));
  for (std::int32_t i = 0; i < node_count_; ++i) {
    mesh.triangles[bucket_[tri_scratch_[i][0]]++] = tri_scratch_[i];
  }
  // bucket_[v] now ends bucket v; bucket v starts where bucket v - 1 ended.
  std::int32_t start = 0;
  for (std::int32_t v = 0; v < count; ++v) {
    const std::int32_t end = bucket_[v];
    if (end - start > 1) std::sort(mesh.triangles.begin() + start, mesh.triangles.begin() + end);
    start = end;
  }

  mesh.forced_splits = forced_splits_;
  mesh.criterion_splits = criterion_splits_;
}

// finish() on the pool, the same mesh for any worker count: the work is cut
// into `bands` parts (rows of the grid, ranges of node slots, ranges of
// vertex ids), each written to disjoint memory; the few values that cross
// parts (vertex and triangle counts per part) are summed serially between
// pool runs. Triangles are partitioned by the band of their first id (ids
// are row-major, so bands of rows are ranges of ids), then each band is
// counting-sorted by first id and its fans sorted, exactly as finish() does
// for the whole range, so concatenating the bands gives finish()'s order.
void Tritree::finish_parallel(Mesh& mesh, ThreadPool& pool) {
  const int w = gray_.width;
  const int h = gray_.height;
  const int bands = std::min(pool.size(), kMaxBands);
  const std::int32_t nodes = node_count_;
  std::int32_t* grid = vertex_id_.data();
  const auto row_band = [&](int b, int* y0, int* y1) { ThreadPool::split_range(0, h, bands, b, y0, y1); };
  const auto node_band = [&](int b, int* i0, int* i1) {
    ThreadPool::split_range(0, nodes, bands, b, i0, i1);
  };
  std::int32_t* const vstart = band_vertex_start_.data();  // bands + 1 entries
  // Band of a vertex id: the last band starting at or before it.
  const auto band_of = [vstart, bands](std::int32_t id) {
    int k = 0;
    while (k + 1 < bands && id >= vstart[k + 1]) ++k;
    return k;
  };

  // 1. Clear the grid, 2. mark every corner (several nodes share a corner:
  // equal values stored concurrently, hence atomic stores).
  pool.run([&](int b) {
    if (b >= bands) return;
    int y0, y1;
    row_band(b, &y0, &y1);
    std::fill(grid + static_cast<std::size_t>(y0) * w, grid + static_cast<std::size_t>(y1) * w, -1);
  });
  pool.run([&](int b) {
    if (b >= bands) return;
    int i0, i1;
    node_band(b, &i0, &i1);
    for (std::int32_t i = i0; i < i1; ++i) {
      const Node& n = nodes_[i];
      for (int j = 0; j < 3; ++j) {
        __atomic_store_n(grid + static_cast<std::size_t>(n.y[j]) * w + n.x[j], 0, __ATOMIC_RELAXED);
      }
    }
  });
  // 3. Vertices per row band, 4. raster-order ids from each band's first id.
  pool.run([&](int b) {
    if (b >= bands) return;
    int y0, y1;
    row_band(b, &y0, &y1);
    std::int32_t count = 0;
    const std::int32_t* end = grid + static_cast<std::size_t>(y1) * w;
    for (const std::int32_t* p = grid + static_cast<std::size_t>(y0) * w; p < end; ++p) count += *p >= 0;
    vstart[b + 1] = count;
  });
  vstart[0] = 0;
  for (int b = 0; b < bands; ++b) vstart[b + 1] += vstart[b];
  const std::int32_t vertex_count = vstart[bands];
  mesh.width = w;
  mesh.height = h;
  mesh.vertices.resize(static_cast<std::size_t>(vertex_count));  // within reserve()
  mesh.row_start.resize(static_cast<std::size_t>(h) + 1);
  mesh.row_start[h] = vertex_count;
  pool.run([&](int b) {
    if (b >= bands) return;
    int y0, y1;
    row_band(b, &y0, &y1);
    std::int32_t id = vstart[b];
    for (int y = y0; y < y1; ++y) {
      mesh.row_start[y] = id;
      std::int32_t* row = grid + static_cast<std::size_t>(y) * w;
      for (int x = 0; x < w; ++x) {
        if (row[x] < 0) continue;
        mesh.vertices[id] = Vertex{x, y};
        row[x] = id++;
      }
    }
  });

  // 5. Canonical rotation per node range, counting the triangles each range
  // sends to each id band; 6. partition them by band (stable within a range).
  std::int32_t* const part = band_part_.data();  // [range][band] counts, then offsets
  pool.run([&](int b) {
    if (b >= bands) return;
    int i0, i1;
    node_band(b, &i0, &i1);
    std::int32_t* cnt = part + b * kMaxBands;
    std::fill(cnt, cnt + bands, 0);
    for (std::int32_t i = i0; i < i1; ++i) {
      const Node& n = nodes_[i];
      Triangle t;
      for (int j = 0; j < 3; ++j) t[j] = grid[static_cast<std::size_t>(n.y[j]) * w + n.x[j]];
      const int r = (t[1] < t[0] && t[1] < t[2]) ? 1 : (t[2] < t[0] && t[2] < t[1]) ? 2 : 0;
      tri_scratch_[i] = Triangle{t[r], t[(r + 1) % 3], t[(r + 2) % 3]};
      ++cnt[band_of(tri_scratch_[i][0])];
    }
  });
  std::int32_t* const tstart = band_tri_start_.data();  // bands + 1 entries
  std::int32_t offset = 0;
  for (int k = 0; k < bands; ++k) {
    tstart[k] = offset;
    for (int b = 0; b < bands; ++b) {
      const std::int32_t c = part[b * kMaxBands + k];
      part[b * kMaxBands + k] = offset;
      offset += c;
    }
  }
  tstart[bands] = offset;
  mesh.triangles.resize(static_cast<std::size_t>(nodes));  // within reserve()
  pool.run([&](int b) {
    if (b >= bands) return;
    int i0, i1;
    node_band(b, &i0, &i1);
    std::int32_t* pos = part + b * kMaxBands;
    for (std::int32_t i = i0; i < i1; ++i) mesh.triangles[pos[band_of(tri_scratch_[i][0])]++] = tri_scratch_[i];
  });

  // 7. Each band: counting sort by first id into tri_scratch_, fans sorted,
  // copied back. Band k's counters start at bucket_[vstart[k] + k], so the
  // bands' counter ranges (one longer than their id ranges) never overlap.
  pool.run([&](int k) {
    if (k >= bands) return;
    const std::int32_t s = tstart[k], e = tstart[k + 1];
    const std::int32_t v0 = vstart[k], nv = vstart[k + 1] - v0;
    std::int32_t* cnt = bucket_.data() + v0 + k;
    std::fill(cnt, cnt + nv + 1, 0);
    for (std::int32_t i = s; i < e; ++i) ++cnt[mesh.triangles[i][0] - v0 + 1];
    for (std::int32_t v = 0; v < nv; ++v) cnt[v + 1] += cnt[v];
    Triangle* dst = tri_scratch_.data() + s;
    for (std::int32_t i = s; i < e; ++i) dst[cnt[mesh.triangles[i][0] - v0]++] = mesh.triangles[i];
    std::int32_t start = 0;
    for (std::int32_t v = 0; v < nv; ++v) {
      const std::int32_t end = cnt[v];
      if (end - start > 1) std::sort(dst + start, dst + end);
      start = end;
    }
    std::copy(dst, dst + (e - s), mesh.triangles.begin() + s);
  });

  mesh.forced_splits = forced_splits_;
  mesh.criterion_splits = criterion_splits_;
}

}  // namespace tristereo
