// Tritree output: the canonical mesh (include/tristereo/mesh.hpp) from the
// leaves, in O(W H + triangles) with the buffers allocated at configure.
// Each step is cut into bands (image rows, node slots, vertex ids) so a pool
// can run it; every band writes only its own part of each array.
#include <algorithm>

#include "platform/thread_pool.hpp"

#include "src/tritree/fill_rule.hpp"
#include "src/tritree/tritree.hpp"

namespace tristereo {

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
  const int parts = (pool != nullptr) ? pool->size() : 1;
  const auto run = [&](const auto& step) {
    if (parts > 1) {
      pool->run([&](int part) { step(part); });
    } else {
      step(0);
    }
  };
  const auto grid_row = [&](int y) { return vertex_id_.data() + static_cast<std::size_t>(y) * w; };
  mesh.width = w;
  mesh.height = h;
  mesh.row_start.resize(static_cast<std::size_t>(h) + 1);

  // Vertex grid: clear, then mark every leaf corner. With several writers a
  // corner is marked only by the leaf that owns its pixel (exactly one under
  // the fill rule, and it has the corner as a vertex: the mesh is conforming),
  // so no two threads write the same cell.
  run([&](int part) {
    int y0 = 0, y1 = 0;
    ThreadPool::split_range(0, h, parts, part, &y0, &y1);
    std::fill(grid_row(y0), grid_row(y1), -1);
  });
  run([&](int part) {
    for_each_slot_of_part(part, parts, [&](std::int32_t s) {
      const Node& n = nodes_[s];
      for (int j = 0; j < 3; ++j) {
        if (parts > 1 &&
            !owns_pixel(vertex(n, 0), vertex(n, 1), vertex(n, 2), n.x[j], n.y[j], w, h)) {
          continue;
        }
        grid_row(n.y[j])[n.x[j]] = 0;
      }
    });
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
  });

  // Triangles: rotated so the smallest id comes first (orientation kept),
  // counting-sorted by that id, then each vertex's small fan sorted. A part
  // owns a band of first ids and collects its triangles from all leaves.
  std::int32_t tri_count = initial_slots_;
  for (int g = 0; g < region_count_; ++g) tri_count += regions_[g].next_slot - regions_[g].slot_begin;
  run([&](int part) {
    for_each_slot_of_part(part, parts, [&](std::int32_t s) {
      const Node& n = nodes_[s];
      Triangle t;
      for (int j = 0; j < 3; ++j) t[j] = grid_row(n.y[j])[n.x[j]];
      const int r = (t[1] < t[0] && t[1] < t[2]) ? 1 : (t[2] < t[0] && t[2] < t[1]) ? 2 : 0;
      tri_scratch_[s] = Triangle{t[r], t[(r + 1) % 3], t[(r + 2) % 3]};
    });
  });
  run([&](int part) {
    int v0 = 0, v1 = 0;
    ThreadPool::split_range(0, count, parts, part, &v0, &v1);
    std::fill(bucket_.begin() + v0, bucket_.begin() + v1, 0);
    for_each_slot([&](std::int32_t s) {
      const std::int32_t first = tri_scratch_[s][0];
      if (first >= v0 && first < v1) ++bucket_[first];
    });
  });
  std::int32_t start = 0;
  for (std::int32_t v = 0; v < count; ++v) {
    const std::int32_t n = bucket_[v];
    bucket_[v] = start;
    start += n;
  }
  mesh.triangles.resize(static_cast<std::size_t>(tri_count));
  run([&](int part) {
    int v0 = 0, v1 = 0;
    ThreadPool::split_range(0, count, parts, part, &v0, &v1);
    if (v0 == v1) return;
    const std::int32_t band_begin = bucket_[v0];
    for_each_slot([&](std::int32_t s) {
      const std::int32_t first = tri_scratch_[s][0];
      if (first >= v0 && first < v1) mesh.triangles[bucket_[first]++] = tri_scratch_[s];
    });
    // bucket_[v] now ends bucket v; bucket v starts where bucket v - 1 ended.
    std::int32_t begin = band_begin;
    for (std::int32_t v = v0; v < v1; ++v) {
      const std::int32_t end = bucket_[v];
      if (end - begin > 1) std::sort(mesh.triangles.begin() + begin, mesh.triangles.begin() + end);
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
