// Triangles that straddle a depth edge (docs/model.md section 4, "Depth
// edges"): a plane through a foreground and a background vertex puts the
// pixels between them at depths that neither surface has. Such a triangle's
// pixels take the disparity of the vertex nearest to them in intensity
// instead, the vertex most likely on the same surface.
#pragma once

#include <cstdint>

#include "src/interp/interpolate_state.hpp"
#include "tristereo/image.hpp"
#include "tristereo/mesh.hpp"

namespace tristereo {

// Whether triangle (da, db, dc) (Q4, all valid) straddles a depth edge: its
// vertex disparities spread over more than spread_q4 (> 0).
inline bool straddles_depth_edge(int da, int db, int dc, int spread_q4) {
  const int lo = da < db ? (da < dc ? da : dc) : (db < dc ? db : dc);
  const int hi = da > db ? (da > dc ? da : dc) : (db > dc ? db : dc);
  return hi - lo > spread_q4;
}

// For every triangle of [tri_begin, tri_end) whose three vertices are valid
// and that straddles a depth edge (spread_q4 > 0): every pixel P it owns
// (src/tritree/fill_rule.hpp) that is not one of its vertices takes the
// disparity of the vertex V minimising |gray(P) - gray(V)|, ties to the
// smaller disparity and then the smaller confidence; with `conf`, P's
// confidence is V's and its state follows. A vertex's own pixel keeps its
// disparity. Runs after the planes of the pixels these triangles own (the
// pipeline: a row of tiles' triangles after that row's midpoints, the
// stretched leaves after their own planes) and overwrites only those pixels,
// so disjoint ranges may run on different workers. `gray` is the image the
// mesh was built on (mesh.width x mesh.height). No argument checks.
void interpolate_edge_triangles(const Mesh& mesh, const std::int16_t* vertex_disp_q4,
                                ImageView<const std::uint8_t> gray, int spread_q4, int tri_begin, int tri_end,
                                ImageView<std::int16_t> disp_q4, const ConfidenceMaps* conf = nullptr);

// The same on leaves[0, count) (vertex ids into mesh.vertices): the
// stretched leaves, after their planes (TritreeGrid::stretched).
void interpolate_edge_leaves(const Triangle* leaves, std::size_t count, const Mesh& mesh,
                             const std::int16_t* vertex_disp_q4, ImageView<const std::uint8_t> gray, int spread_q4,
                             ImageView<std::int16_t> disp_q4, const ConfidenceMaps* conf = nullptr);

}  // namespace tristereo
