#include "src/interp/interpolate_state.hpp"

#include <algorithm>
#include <cstring>

#include "src/tritree/fill_rule.hpp"

namespace tristereo {

void interpolate_state_triangles(const Mesh& mesh, const std::uint8_t* vertex_state,
                                 const std::uint8_t* vertex_confidence, int tri_begin, int tri_end,
                                 ImageView<std::uint8_t> state, ImageView<std::uint8_t> confidence) {
  const int w = mesh.width, h = mesh.height;
  for (int t = tri_begin; t < tri_end; ++t) {
    const Triangle& tri = mesh.triangles[static_cast<std::size_t>(t)];
    const std::uint8_t s = std::min({vertex_state[tri[0]], vertex_state[tri[1]], vertex_state[tri[2]]});
    const std::uint8_t c =
        std::min({vertex_confidence[tri[0]], vertex_confidence[tri[1]], vertex_confidence[tri[2]]});
    for_each_owned_span(mesh.vertices[static_cast<std::size_t>(tri[0])],
                        mesh.vertices[static_cast<std::size_t>(tri[1])],
                        mesh.vertices[static_cast<std::size_t>(tri[2])], w, h, [&](int y, int x0, int x1) {
                          std::memset(state.row(y) + x0, s, static_cast<std::size_t>(x1 - x0));
                          std::memset(confidence.row(y) + x0, c, static_cast<std::size_t>(x1 - x0));
                        });
  }
}

}  // namespace tristereo
