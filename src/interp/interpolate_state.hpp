// Pixel state and confidence from the mesh vertices' (docs/model.md section 7).
#pragma once

#include <cstdint>

#include "tristereo/image.hpp"
#include "tristereo/mesh.hpp"

namespace tristereo {

// For every pixel owned (src/tritree/fill_rule.hpp) by the triangles
// [tri_begin, tri_end) of `mesh`: state = the smallest vertex_state of the
// triangle's three vertices, confidence = the smallest vertex_confidence.
// Other pixels are not touched, so disjoint ranges may run on different
// threads. No argument checks: both maps are mesh.width x mesh.height, the
// range is inside the mesh (the pipeline's invariants).
void interpolate_state_triangles(const Mesh& mesh, const std::uint8_t* vertex_state,
                                 const std::uint8_t* vertex_confidence, int tri_begin, int tri_end,
                                 ImageView<std::uint8_t> state, ImageView<std::uint8_t> confidence);

}  // namespace tristereo
