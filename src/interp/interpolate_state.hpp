// Pixel state and confidence from the mesh vertices' (docs/model.md section 7).
#pragma once

#include <cstdint>

#include "tristereo/image.hpp"
#include "tristereo/mesh.hpp"

namespace tristereo {

// For every pixel owned (src/tritree/fill_rule.hpp) by the triangles
// [tri_begin, tri_end) of `mesh`: the smallest vertex_confidence of the
// triangle's three vertices. Other pixels are not touched, so disjoint ranges
// may run on different threads. No argument checks: the map is mesh.width x
// mesh.height, the range is inside the mesh (the pipeline's invariants).
// The pixel's state, the smallest of its vertices' states, follows from this
// confidence (state_of_confidence: the state is monotone in the confidence),
// so it is derived per pixel afterwards instead of written per triangle.
void interpolate_confidence_triangles(const Mesh& mesh, const std::uint8_t* vertex_confidence, int tri_begin,
                                      int tri_end, ImageView<std::uint8_t> confidence);

}  // namespace tristereo
