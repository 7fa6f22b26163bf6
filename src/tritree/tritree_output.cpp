// Tritree output: the canonical mesh (include/tristereo/mesh.hpp) from the
// leaves, in O(W H + triangles) with the buffers allocated at configure.
// Each step is cut into bands (image rows, node slots, vertex ids) so a pool
// can run it; every band writes only its own part of each array.
#include <algorithm>

#include "platform/thread_pool.hpp"

#include "src/tritree/fill_rule.hpp"
#include "src/tritree/tritree.hpp"

namespace tristereo {

namespace {

// Sorts one vertex's fan: a few triangles that all start with the same id, so
// the order is that of (second, third) id. Insertion sort: fans hold about six
// triangles, and std::sort's set-up cost more than the sorting.
void sort_fan(Triangle* begin, Triangle* end) {
  for (Triangle* i = begin + 1; i < end; ++i) {
    const Triangle t = *i;
    Triangle* j = i;
    for (; j > begin; --j) {
      const Triangle& prev = *(j - 1);
      if (prev[1] < t[1] || (prev[1] == t[1] && prev[2] < t[2])) break;
      *j = prev;
    }
    *j = t;
  }
}

}  // namespace

// Calls fn(slot) for the leaves of part `part` of `parts`: a share of the
// slots that existed before the regions, and the regions g with g % parts == part.
template <class Fn>
void Tritree::for_each_slot_of_part(int part, int parts, Fn&& fn) const {
  int b = 0, e = 0;
  ThreadPool::split_range(0, initial_slots_, parts, part, &b, &e);
  for (std::int32_t s = b; s < e; ++s) fn(s);
  for (int g = part; g < region_count_; g += parts) {
    for (std::int32_t s = regions_[g].slot_begin; s < regions_[g].next_slot; ++s) fn(s);
  }
}

void Tritree::finish(Mesh& mesh, ThreadPool* pool) {
  const int w = gray_.width;
  const int h = gray_.height;
  // One part per worker, at most kMaxRegions (band_fill_ is sized for that).
  const int parts = (pool != nullptr) ? std::min(pool->size(), kMaxRegions) : 1;
  const auto run = [&](const auto& step) {
    if (parts > 1) {
      pool->run([&](int part) {
        if (part < parts) step(part);
      });
    } else {
      step(0);
    }
  };
  const auto grid_row = [&](int y) { return vertex_id_.data() + static_cast<std::size_t>(y) * w; };
  mesh.width = w;
  mesh.height = h;
  mesh.row_start.resize(static_cast<std::size_t>(h) + 1);

  // Vertex grid: clear, then mark the four corners and every vertex a
  // bisection created. Each of those is distinct (a valid bisection puts its
  // midpoint strictly inside the quadrilateral, or strictly inside a border
  // edge, of two leaves, where no vertex lies), so no two parts write one cell.
  run([&](int part) {
    int y0 = 0, y1 = 0;
    ThreadPool::split_range(0, h, parts, part, &y0, &y1);
    std::fill(grid_row(y0), grid_row(y1), -1);
  });
  // Leaf chunks: one per region, each worker's own regions (its home in the
  // rounds, see refine()) first, so it reads nodes its core wrote.
  const bool banded = parts > 1;
  const int chunks = banded ? region_count_ : 1;
  chunk_homes_.reset(chunks, parts);
  run([&](int part) {
    const auto mark = [&](const Vertex* v, std::int32_t n) {
      for (std::int32_t i = 0; i < n; ++i) grid_row(v[i].y)[v[i].x] = 0;
    };
    int b = 0, e = 0;
    ThreadPool::split_range(0, initial_vertices_, parts, part, &b, &e);
    mark(new_vertices_.data() + b, e - b);
    int g0 = 0, g1 = 0;
    if (banded && part < chunk_homes_.homes()) chunk_homes_.home_range(part, &g0, &g1);
    if (!banded) g1 = region_count_;
    for (int g = g0; g < g1; ++g) {
      mark(new_vertices_.data() + regions_[g].slot_begin, regions_[g].vertex_count);
    }
    if (part == 0) {
      grid_row(0)[0] = grid_row(0)[w - 1] = grid_row(h - 1)[0] = grid_row(h - 1)[w - 1] = 0;
    }
  });

  // Vertex ids in raster order: count per row, prefix sum, then number them.
  run([&](int part) {
    int y0 = 0, y1 = 0;
    ThreadPool::split_range(0, h, parts, part, &y0, &y1);
    for (int y = y0; y < y1; ++y) {
      const std::int32_t* row = grid_row(y);
      mesh.row_start[y + 1] = static_cast<std::int32_t>(std::count(row, row + w, 0));
    }
  });
  mesh.row_start[0] = 0;
  for (int y = 0; y < h; ++y) mesh.row_start[y + 1] += mesh.row_start[y];
  const std::int32_t count = mesh.row_start[h];
  mesh.vertices.resize(static_cast<std::size_t>(count));

  // Triangles, rotated so the smallest id comes first (orientation kept),
  // sorted by that id and then within each vertex's fan. Output band b holds
  // the first ids of rows [row_cut(b), row_cut(b + 1)), cut at equal vertex
  // counts; a triangle's first vertex is one of its topmost, so its band is
  // known from the leaf's rows alone, before any id exists. The leaves are
  // taken in chunks (a region each, with a share of the slots older than the
  // regions): a chunk's leaves are counted per band while the vertices are
  // numbered, then rotated straight into the chunk's share of each band in
  // tri_banded_, and each band is counting-sorted on its own. Chunks and
  // bands are fixed, so any worker may take any of them (on demand, like the
  // rounds) and the output does not depend on who did.
  const int bands = banded ? std::min(kMaxRegions, kRegionsPerWorker * parts) : 1;
  std::int32_t row_cut[kMaxRegions + 1];  // first row of each band, then h
  for (int b = 0; b < bands; ++b) {
    const std::int64_t target = std::int64_t{count} * b / bands;
    row_cut[b] = static_cast<std::int32_t>(
        std::lower_bound(mesh.row_start.begin(), mesh.row_start.end() - 1, target) - mesh.row_start.begin());
  }
  row_cut[bands] = h;
  for (int b = 0; b < bands; ++b) {
    std::fill(band_of_row_.begin() + row_cut[b], band_of_row_.begin() + row_cut[b + 1], b);
  }
  const auto band_of = [&](const Node& n) {
    return band_of_row_[static_cast<std::size_t>(std::min({n.y[0], n.y[1], n.y[2]}))];
  };
  std::int32_t* fill = band_fill_.data();  // fill[chunk * bands + band]

  // Vertex ids in raster order; meanwhile, the triangles of each chunk are
  // counted per band.
  run([&](int part) {
    int y0 = 0, y1 = 0;
    ThreadPool::split_range(0, h, parts, part, &y0, &y1);
    for (int y = y0; y < y1; ++y) {
      std::int32_t* row = grid_row(y);
      std::int32_t id = mesh.row_start[y];
      for (int x = 0; x < w; ++x) {
        if (row[x] < 0) continue;
        row[x] = id;
        mesh.vertices[id++] = Vertex{x, y};
      }
    }
    if (!banded) return;
    chunk_homes_.for_each(part, [&](int c) {
      // On the stack while counting: chunks' rows of band_fill_ share cache
      // lines, and an increment per triangle there would make the cores
      // fight over them.
      std::int32_t mine[kMaxRegions] = {};
      for_each_slot_of_part(c, chunks, [&](std::int32_t s) { ++mine[band_of(nodes_[s])]; });
      std::copy(mine, mine + bands, fill + c * bands);
    });
  });
  // Counts -> starts, band-major (band b holds chunks 0..chunks-1 in order).
  // One band and chunk: every leaf, in slot order.
  std::int32_t band_start[kMaxRegions + 1];
  std::int32_t total = 0;
  if (!banded) {
    fill[0] = 0;
    total = initial_slots_;
    for (int g = 0; g < region_count_; ++g) total += regions_[g].next_slot - regions_[g].slot_begin;
  }
  for (int b = 0; b < bands && banded; ++b) {
    band_start[b] = total;
    for (int c = 0; c < chunks; ++c) {
      const std::int32_t n = fill[c * bands + b];
      fill[c * bands + b] = total;
      total += n;
    }
  }
  band_start[0] = 0;
  band_start[bands] = total;
  mesh.triangles.resize(static_cast<std::size_t>(total));

  const auto on_demand = [&](int n, const auto& fn) {  // fn(i) for i in [0, n), any worker
    finish_chunks_.reset(0, n, 1);
    run([&](int) {
      int i = 0, i_end = 0;
      while (finish_chunks_.next(&i, &i_end)) fn(i);
    });
  };
  chunk_homes_.reset(chunks, parts);
  run([&](int part) {
    chunk_homes_.for_each(part, [&](int c) {
      std::int32_t next[kMaxRegions];
      std::copy(fill + c * bands, fill + (c + 1) * bands, next);
      for_each_slot_of_part(c, chunks, [&](std::int32_t s) {
        const Node& n = nodes_[s];
        Triangle t;
        for (int j = 0; j < 3; ++j) t[j] = grid_row(n.y[j])[n.x[j]];
        const int r = (t[1] < t[0] && t[1] < t[2]) ? 1 : (t[2] < t[0] && t[2] < t[1]) ? 2 : 0;
        tri_banded_[static_cast<std::size_t>(next[band_of(n)]++)] = Triangle{t[r], t[(r + 1) % 3], t[(r + 2) % 3]};
      });
    });
  });
  on_demand(bands, [&](int b) {
    const std::int32_t v0 = mesh.row_start[static_cast<std::size_t>(row_cut[b])];
    const std::int32_t v1 = mesh.row_start[static_cast<std::size_t>(row_cut[b + 1])];
    const Triangle* first = tri_banded_.data() + band_start[b];
    const Triangle* last = tri_banded_.data() + band_start[b + 1];
    std::fill(bucket_.begin() + v0, bucket_.begin() + v1, 0);
    for (const Triangle* t = first; t != last; ++t) ++bucket_[(*t)[0]];
    std::int32_t start = band_start[b];
    for (std::int32_t v = v0; v < v1; ++v) {
      const std::int32_t n = bucket_[v];
      bucket_[v] = start;
      start += n;
    }
    for (const Triangle* t = first; t != last; ++t) mesh.triangles[bucket_[(*t)[0]]++] = *t;
    // bucket_[v] now ends bucket v; bucket v starts where bucket v - 1 ended.
    std::int32_t begin = band_start[b];
    for (std::int32_t v = v0; v < v1; ++v) {
      const std::int32_t end = bucket_[v];
      if (end - begin > 1) sort_fan(mesh.triangles.data() + begin, mesh.triangles.data() + end);
      begin = end;
    }
  });

  mesh.forced_splits = forced_splits_;
  mesh.criterion_splits = criterion_splits_;
  for (int g = 0; g < region_count_; ++g) {
    mesh.forced_splits += regions_[g].forced_splits;
    mesh.criterion_splits += regions_[g].criterion_splits;
  }
}

}  // namespace tristereo
