// The pixels a small mesh triangle owns, as a bit mask from a table built
// once from the fill rule (src/tritree/fill_rule.hpp): the interpolation's
// fast path for the finest leaves, which are most of a fine mesh.
#pragma once

#include <algorithm>
#include <cstdint>

#include "src/tritree/fill_rule.hpp"
#include "tristereo/mesh.hpp"

namespace tristereo {

// Pixels owned by a small triangle, for triangles whose corners B and C lie
// within 2 pixels of A and that do not reach the image's last row or column
// (where the fill rule's tie breaks the other way): most of a fine mesh. Bit
// (dy + 2) * 5 + (dx + 2) is pixel A + (dx, dy); indexed by small_key().
struct SmallTriangleMasks {
  std::uint32_t mask[625];
};

inline int small_key(int ux, int uy, int vx, int vy) {
  return (((ux + 2) * 5 + (uy + 2)) * 5 + (vx + 2)) * 5 + (vy + 2);
}

// Built once from the fill rule itself (owns_pixel, far from any border).
inline const SmallTriangleMasks& small_triangle_masks() {
  static const SmallTriangleMasks table = [] {
    SmallTriangleMasks t{};
    const int kFar = 64, kSize = 128;
    for (int ux = -2; ux <= 2; ++ux)
      for (int uy = -2; uy <= 2; ++uy)
        for (int vx = -2; vx <= 2; ++vx)
          for (int vy = -2; vy <= 2; ++vy) {
            if (ux * vy - uy * vx <= 0) continue;
            const Vertex a{kFar, kFar}, b{kFar + ux, kFar + uy}, c{kFar + vx, kFar + vy};
            std::uint32_t m = 0;
            for (int dy = -2; dy <= 2; ++dy)
              for (int dx = -2; dx <= 2; ++dx)
                if (owns_pixel(a, b, c, kFar + dx, kFar + dy, kSize, kSize)) m |= 1u << ((dy + 2) * 5 + dx + 2);
            t.mask[small_key(ux, uy, vx, vy)] = m;
          }
    return t;
  }();
  return table;
}

// Whether triangle (a, b, c) takes the table: corners B and C within 2
// pixels of A, none on the image's last row or column (width w, height h).
inline bool is_small_triangle(const Vertex& a, const Vertex& b, const Vertex& c, int w, int h) {
  const int ux = b.x - a.x, uy = b.y - a.y, vx = c.x - a.x, vy = c.y - a.y;
  return ux >= -2 && ux <= 2 && uy >= -2 && uy <= 2 && vx >= -2 && vx <= 2 && vy >= -2 && vy <= 2 &&
         std::max({a.x, b.x, c.x}) < w - 1 && std::max({a.y, b.y, c.y}) < h - 1;
}

}  // namespace tristereo
