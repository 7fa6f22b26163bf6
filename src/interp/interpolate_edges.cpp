#include "src/interp/interpolate_edges.hpp"

#include <algorithm>
#include <cstdlib>

#include "src/interp/small_triangles.hpp"
#include "src/select/confidence.hpp"
#include "src/tritree/fill_rule.hpp"
#include "tristereo/fixed_point.hpp"

namespace tristereo {

namespace {

// Triangles tested at a time: the straddling ones (a few percent) are listed
// without a branch, then written.
constexpr int kBlock = 256;

// The rule's order as one integer, smallest first: the intensity distance,
// then the disparity, then the confidence (8 + 16 + 8 bits).
inline std::uint32_t vertex_key(int disp_q4, std::uint8_t confidence) {
  return (static_cast<std::uint32_t>(disp_q4 + 32768) << 8) | confidence;
}
inline std::uint32_t with_distance(std::uint32_t key, int gray_p, int gray_v) {
  return key + (static_cast<std::uint32_t>(std::abs(gray_p - gray_v)) << 24);
}
inline std::int16_t disp_of_key(std::uint32_t key) {
  return static_cast<std::int16_t>(static_cast<int>((key >> 8) & 0xFFFFu) - 32768);
}

// One straddling triangle: every pixel it owns from its corners' keys, a
// corner's own pixel (when the triangle owns it) from that corner alone.
void write_triangle(const SmallTriangleMasks& masks, const Vertex& a, const Vertex& b, const Vertex& c,
                    std::uint32_t ka, std::uint32_t kb, std::uint32_t kc, ImageView<const std::uint8_t> gray,
                    ImageView<std::int16_t> disp_q4, const ConfidenceMaps* conf) {
  const int w = disp_q4.width, h = disp_q4.height;
  const int ga = gray.row(a.y)[a.x], gb = gray.row(b.y)[b.x], gc = gray.row(c.y)[c.x];
  const auto put = [&](int x, int y, std::uint32_t key) {
    disp_q4.row(y)[x] = disp_of_key(key);
    if (conf != nullptr) {
      const auto cf = static_cast<std::uint8_t>(key & 0xFFu);
      conf->confidence.row(y)[x] = cf;
      conf->state.row(y)[x] = state_of_confidence(cf);
    }
  };
  const auto nearest = [&](int p) {
    return std::min({with_distance(ka, p, ga), with_distance(kb, p, gb), with_distance(kc, p, gc)});
  };
  if (is_small_triangle(a, b, c, w, h)) {
    const int ux = b.x - a.x, uy = b.y - a.y, vx = c.x - a.x, vy = c.y - a.y;
    std::uint32_t m = masks.mask[small_key(ux, uy, vx, vy)];
    // Bit (dy + 2) * 5 + dx + 2 is A + (dx, dy): the corners' own bits.
    const std::uint32_t bit_a = 1u << 12, bit_b = 1u << ((uy + 2) * 5 + ux + 2), bit_c = 1u << ((vy + 2) * 5 + vx + 2);
    if ((m & bit_a) != 0) put(a.x, a.y, ka);
    if ((m & bit_b) != 0) put(b.x, b.y, kb);
    if ((m & bit_c) != 0) put(c.x, c.y, kc);
    m &= ~(bit_a | bit_b | bit_c);
    while (m != 0) {
      const int bit = __builtin_ctz(m);
      m &= m - 1;
      const int x = a.x + bit % 5 - 2, y = a.y + bit / 5 - 2;
      put(x, y, nearest(gray.row(y)[x]));
    }
    return;
  }
  for_each_owned_span(a, b, c, w, h, [&](int y, int x0, int x1) {
    const std::uint8_t* g = gray.row(y);
    for (int x = x0; x < x1; ++x) put(x, y, nearest(g[x]));
  });
  if (owns_pixel(a, b, c, a.x, a.y, w, h)) put(a.x, a.y, ka);
  if (owns_pixel(a, b, c, b.x, b.y, w, h)) put(b.x, b.y, kb);
  if (owns_pixel(a, b, c, c.x, c.y, w, h)) put(c.x, c.y, kc);
}

}  // namespace

namespace {

// The rule on tris[0, count) (vertex ids into mesh.vertices).
void edge_triangles(const Triangle* tris, std::size_t count, const Mesh& mesh, const std::int16_t* vertex_disp_q4,
                    ImageView<const std::uint8_t> gray, int spread_q4, ImageView<std::int16_t> disp_q4,
                    const ConfidenceMaps* conf) {
  if (spread_q4 <= 0) return;
  const Vertex* vertices = mesh.vertices.data();
  const SmallTriangleMasks& masks = small_triangle_masks();
  const unsigned two_spread = 2u * static_cast<unsigned>(spread_q4);
  std::int32_t listed[kBlock];
  for (std::size_t t0 = 0; t0 < count; t0 += kBlock) {
    const auto t1 = static_cast<int>(std::min<std::size_t>(count - t0, kBlock));
    const Triangle* block = tris + t0;
    int n = 0;
    for (int t = 0; t < t1; ++t) {
      const Triangle& tri = block[t];
      const int da = vertex_disp_q4[tri[0]], db = vertex_disp_q4[tri[1]], dc = vertex_disp_q4[tri[2]];
      // A spread over T is some pair over T apart: |u - v| > T exactly when
      // u - v + T, as unsigned, exceeds 2T. No minimum and maximum: the
      // compiler made them branches, mispredicted on every other triangle.
      const unsigned edge = static_cast<unsigned>(static_cast<unsigned>(da - db + spread_q4) > two_spread) |
                            static_cast<unsigned>(static_cast<unsigned>(db - dc + spread_q4) > two_spread) |
                            static_cast<unsigned>(static_cast<unsigned>(da - dc + spread_q4) > two_spread);
      listed[n] = t;
      n += static_cast<int>(edge);
    }
    // Invalid corners are rare after the fill: tested only here (three
    // invalid ones spread over nothing and are not listed).
    for (int j = 0; j < n; ++j) {
      const Triangle& tri = block[listed[j]];
      if (vertex_disp_q4[tri[0]] == kInvalidDispQ4 || vertex_disp_q4[tri[1]] == kInvalidDispQ4 ||
          vertex_disp_q4[tri[2]] == kInvalidDispQ4)
        continue;
      const auto key = [&](std::int32_t v) {
        return vertex_key(vertex_disp_q4[v], conf != nullptr ? conf->vertex_confidence[v] : std::uint8_t{0});
      };
      write_triangle(masks, vertices[tri[0]], vertices[tri[1]], vertices[tri[2]], key(tri[0]), key(tri[1]),
                     key(tri[2]), gray, disp_q4, conf);
    }
  }
}

}  // namespace

void interpolate_edge_triangles(const Mesh& mesh, const std::int16_t* vertex_disp_q4,
                                ImageView<const std::uint8_t> gray, int spread_q4, int tri_begin, int tri_end,
                                ImageView<std::int16_t> disp_q4, const ConfidenceMaps* conf) {
  if (tri_end <= tri_begin) return;
  edge_triangles(mesh.triangles.data() + tri_begin, static_cast<std::size_t>(tri_end - tri_begin), mesh,
                 vertex_disp_q4, gray, spread_q4, disp_q4, conf);
}

void interpolate_edge_leaves(const Triangle* leaves, std::size_t count, const Mesh& mesh,
                             const std::int16_t* vertex_disp_q4, ImageView<const std::uint8_t> gray, int spread_q4,
                             ImageView<std::int16_t> disp_q4, const ConfidenceMaps* conf) {
  edge_triangles(leaves, count, mesh, vertex_disp_q4, gray, spread_q4, disp_q4, conf);
}

}  // namespace tristereo
