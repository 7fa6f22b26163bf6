// Dense disparity from the sample disparities: one plane per mesh triangle
// (docs/model.md section 4).
#pragma once

#include <cstdint>

#include "tristereo/image.hpp"
#include "tristereo/mesh.hpp"

namespace tristereo {

// Writes disp_q4(P) for every pixel P owned (src/tritree/fill_rule.hpp) by the
// triangles [tri_begin, tri_end) of `mesh`: the plane through the triangle's
// three (x, y, disparity_q4) vertices, rounded half up,
//   disp_q4(P) = floor((2 N(P) + area2) / (2 area2)),
//   N(P) = area2 dA - n_x (Px - Ax) - n_y (Py - Ay),  n = (B - A) x (C - A).
// A triangle with any vertex at kInvalidDispQ4 writes kInvalidDispQ4. Other
// pixels are not touched, so disjoint triangle ranges may run on different
// threads. Exact: N < 2^43 in int64, and the quotient is stepped along each
// span with an exact quotient/remainder pair (no per-pixel division).
// Throws Error (nothing written) when disp_q4 is not mesh.width x mesh.height,
// has null data or a stride below width * 2 bytes, vertex_disp_q4 is null, or
// the range is not inside [0, triangles.size()]. Vertex ids and orientation
// are preconditions (the tritree's output invariants).
void interpolate_triangles(const Mesh& mesh, const std::int16_t* vertex_disp_q4,
                           int tri_begin, int tri_end, ImageView<std::int16_t> disp_q4);

// One triangle (a, b, c) with positive orientation, as above: writes the
// pixels of disp_q4 (the whole image) it owns. No argument checks.
void interpolate_triangle(const Vertex& a, const Vertex& b, const Vertex& c, std::int16_t disp_a,
                          std::int16_t disp_b, std::int16_t disp_c, ImageView<std::int16_t> disp_q4);

}  // namespace tristereo
