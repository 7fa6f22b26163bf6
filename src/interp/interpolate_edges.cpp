#include "src/interp/interpolate_edges.hpp"

#include <algorithm>
#include <cstdlib>

#include "src/select/confidence.hpp"
#include "src/tritree/fill_rule.hpp"
#include "tristereo/fixed_point.hpp"

namespace tristereo {

namespace {

struct Corner {
  Vertex at;
  int disp_q4;
  int gray;
  std::uint8_t confidence;
};

}  // namespace

void interpolate_edge_triangles(const Mesh& mesh, const std::int16_t* vertex_disp_q4,
                                ImageView<const std::uint8_t> gray, int spread_q4, int tri_begin, int tri_end,
                                ImageView<std::int16_t> disp_q4, const ConfidenceMaps* conf) {
  if (spread_q4 <= 0) return;
  const int w = disp_q4.width, h = disp_q4.height;
  for (int t = tri_begin; t < tri_end; ++t) {
    const Triangle& tri = mesh.triangles[static_cast<std::size_t>(t)];
    const int da = vertex_disp_q4[tri[0]], db = vertex_disp_q4[tri[1]], dc = vertex_disp_q4[tri[2]];
    if (da == kInvalidDispQ4 || db == kInvalidDispQ4 || dc == kInvalidDispQ4) continue;
    if (!straddles_depth_edge(da, db, dc, spread_q4)) continue;
    Corner k[3];
    for (int i = 0; i < 3; ++i) {
      const Vertex& v = mesh.vertices[static_cast<std::size_t>(tri[static_cast<std::size_t>(i)])];
      k[i] = Corner{v, vertex_disp_q4[tri[static_cast<std::size_t>(i)]], gray.row(v.y)[v.x],
                    conf != nullptr ? conf->vertex_confidence[tri[static_cast<std::size_t>(i)]] : std::uint8_t{0}};
    }
    // The tie order: smaller disparity first, then smaller confidence; the
    // strict comparisons below then keep the first of equals.
    std::sort(k, k + 3, [](const Corner& p, const Corner& q) {
      return p.disp_q4 != q.disp_q4 ? p.disp_q4 < q.disp_q4 : p.confidence < q.confidence;
    });
    // The fill rule needs the mesh's own corner order.
    const Vertex& a = mesh.vertices[static_cast<std::size_t>(tri[0])];
    const Vertex& b = mesh.vertices[static_cast<std::size_t>(tri[1])];
    const Vertex& c = mesh.vertices[static_cast<std::size_t>(tri[2])];
    for_each_owned_span(a, b, c, w, h, [&](int y, int x0, int x1) {
      const std::uint8_t* g = gray.row(y);
      std::int16_t* out = disp_q4.row(y);
      std::uint8_t* cf = conf != nullptr ? conf->confidence.row(y) : nullptr;
      std::uint8_t* st = conf != nullptr ? conf->state.row(y) : nullptr;
      for (int x = x0; x < x1; ++x) {
        int best = 0;
        const int p = g[x];
        int e = std::abs(p - k[0].gray);
        for (int i = 1; i < 3; ++i) {
          const int ei = std::abs(p - k[i].gray);
          if (ei < e) e = ei, best = i;
        }
        for (int i = 0; i < 3; ++i)
          if (k[i].at.x == x && k[i].at.y == y) best = i;  // a vertex's own pixel
        out[x] = static_cast<std::int16_t>(k[best].disp_q4);
        if (cf != nullptr) {
          cf[x] = k[best].confidence;
          st[x] = state_of_confidence(k[best].confidence);
        }
      }
    });
  }
}

}  // namespace tristereo
