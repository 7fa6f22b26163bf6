// Exact integer geometry of the tritree (docs/model.md section 1, "Geometry"):
// orientation, the strict total order on edges that makes "the longest edge"
// unique, the snapped midpoint and the validity of a bisection.
// Coordinates are < 4096, so every product here is below 2^26.
#pragma once

#include <cstdint>
#include <utility>

#include "tristereo/mesh.hpp"

namespace tristereo {

// Twice the signed area of (a, b, c); > 0 for the stored orientation.
inline std::int64_t area2_of(const Vertex& a, const Vertex& b, const Vertex& c) {
  return std::int64_t{b.x - a.x} * (c.y - a.y) - std::int64_t{b.y - a.y} * (c.x - a.x);
}

// Raster key (y, x) packed so that integer order is lexicographic order.
inline std::int64_t vertex_key(const Vertex& v) {
  return (std::int64_t{v.y} << 16) | v.x;
}

// Strict edge order (len2, key(lower endpoint), key(upper endpoint)).
inline bool edge_less(Vertex p0, Vertex p1, Vertex q0, Vertex q1) {
  const std::int64_t lp = std::int64_t{p1.x - p0.x} * (p1.x - p0.x) +
                          std::int64_t{p1.y - p0.y} * (p1.y - p0.y);
  const std::int64_t lq = std::int64_t{q1.x - q0.x} * (q1.x - q0.x) +
                          std::int64_t{q1.y - q0.y} * (q1.y - q0.y);
  if (lp != lq) return lp < lq;
  std::int64_t p_lo = vertex_key(p0), p_hi = vertex_key(p1);
  std::int64_t q_lo = vertex_key(q0), q_hi = vertex_key(q1);
  if (p_lo > p_hi) std::swap(p_lo, p_hi);
  if (q_lo > q_hi) std::swap(q_lo, q_hi);
  if (p_lo != q_lo) return p_lo < q_lo;
  return p_hi < q_hi;
}

// Index i of the longest edge (v[i], v[(i + 1) % 3]). Lengths first in int32
// (< 2^25 for coordinates < 4096); the full edge order only breaks ties.
inline int longest_edge_index(const Vertex v[3]) {
  std::int32_t len2[3];
  for (int i = 0; i < 3; ++i) {
    const std::int32_t dx = v[(i + 1) % 3].x - v[i].x;
    const std::int32_t dy = v[(i + 1) % 3].y - v[i].y;
    len2[i] = dx * dx + dy * dy;
  }
  int best = 0;
  for (int i = 1; i < 3; ++i) {
    if (len2[i] > len2[best] ||
        (len2[i] == len2[best] &&
         edge_less(v[best], v[(best + 1) % 3], v[i], v[(i + 1) % 3]))) {
      best = i;
    }
  }
  return best;
}

// Midpoint of an edge, floored onto the pixel grid; symmetric in (p, q), so
// both triangles sharing an edge split it at the same vertex.
inline Vertex snapped_midpoint(const Vertex& p, const Vertex& q) {
  return Vertex{(p.x + q.x) >> 1, (p.y + q.y) >> 1};
}

// Smallest child area2 a bisection may create (area >= 1 px^2, the paper's rule).
constexpr std::int64_t kMinChildArea2 = 2;

// True when bisecting (a, b, c) on edge ab at m gives children (a, m, c) and
// (m, b, c) that both have area2 >= 2 (this also rejects a snap that pushed m
// onto or across another edge).
inline bool half_bisection_valid(const Vertex& a, const Vertex& b, const Vertex& c,
                                 const Vertex& m) {
  return area2_of(a, m, c) >= kMinChildArea2 && area2_of(m, b, c) >= kMinChildArea2;
}

}  // namespace tristereo
