// Pixel state and confidence from the mesh vertices' (docs/model.md section
// 7). Most pixels get theirs from the midpoint hierarchy, beside their
// disparity (src/interp/interpolate_midpoints.hpp); these are the triangles'
// rule for the others (the stretched leaves, a 2-pixel strip, the triangles
// with an invalid vertex).
#pragma once

#include <cstdint>

#include "tristereo/image.hpp"
#include "tristereo/mesh.hpp"

namespace tristereo {

// The maps the interpolation writes beside the disparity when asked: from
// vertex_confidence (one per mesh vertex, 0 exactly for the invalid ones),
// the pixel confidence and state, mesh.width x mesh.height.
struct ConfidenceMaps {
  const std::uint8_t* vertex_confidence = nullptr;
  ImageView<std::uint8_t> confidence;
  ImageView<std::uint8_t> state;
};

// Every pixel P the triangle (a, b, c) (positive orientation) owns: when
// `invalid` (some vertex's disparity is), confidence and state 0; else the
// smallest confidence of the vertices whose weight in the plane at P is not
// zero (a vertex's weight is zero exactly when P lies on the opposite edge),
// and the state that confidence implies. No argument checks.
void confidence_triangle(const Vertex& a, const Vertex& b, const Vertex& c, std::uint8_t conf_a,
                         std::uint8_t conf_b, std::uint8_t conf_c, bool invalid, const ConfidenceMaps& maps);

}  // namespace tristereo
