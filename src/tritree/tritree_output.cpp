// Tritree output: the canonical mesh (include/tristereo/mesh.hpp) from the
// leaves, in O(W H + triangles) with the buffers allocated at configure.
#include <algorithm>

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

}  // namespace tristereo
