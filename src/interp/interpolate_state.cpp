#include "src/interp/interpolate_state.hpp"

#include <algorithm>

#include "src/interp/interpolate_planes.hpp"

namespace tristereo {

void interpolate_confidence_triangles(const Mesh& mesh, const std::uint8_t* vertex_confidence, int tri_begin,
                                      int tri_end, ImageView<std::uint8_t> confidence) {
  for (int t = tri_begin; t < tri_end; ++t) {
    const Triangle& tri = mesh.triangles[static_cast<std::size_t>(t)];
    const std::uint8_t c =
        std::min({vertex_confidence[tri[0]], vertex_confidence[tri[1]], vertex_confidence[tri[2]]});
    fill_triangle_u8(mesh.vertices[static_cast<std::size_t>(tri[0])], mesh.vertices[static_cast<std::size_t>(tri[1])],
                     mesh.vertices[static_cast<std::size_t>(tri[2])], c, confidence);
  }
}

}  // namespace tristereo
