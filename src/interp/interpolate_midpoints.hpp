// Dense disparity from the sample disparities by midpoint averages over the
// tritree's hierarchy: the same values as one plane per mesh triangle
// (docs/model.md section 4), without visiting the triangles.
//
// Why it is the same. The interpolant f is continuous and linear on each leaf.
// Every grid point m that is not a vertex is the midpoint of exactly one
// hypotenuse AB of the hierarchy, and AB lies inside (or on the boundary of)
// the leaf that contains m: so f(m) = (f(A) + f(B)) / 2. Going from the tiles'
// corners down to the squares of side 2, every grid point is either a vertex
// (its sample) or the average of two points already known. A leaf of an
// unstretched tritree has area2 = 2^a <= S^2 / 2, so f is an integer multiple
// of 2^-a at grid points: in units of 2^-F (F = log2(S^2 / 2)) every average
// is exact in int32, and the model's rounding floor(N / area2 + 1/2) is
// (v + 2^(F-1)) >> F. Two cases are left to the triangles
// (interpolate_triangle): the stretched leaves on the moved last column and
// row (their planes do not meet the grid's midpoints), and a leaf with an
// invalid vertex (the model invalidates every pixel it owns, which depends on
// the fill rule, not on f).
//
// The pixel confidence (docs/model.md section 7) goes down the same
// hierarchy, the minimum taking the average's place: a grid point that is not
// a vertex gets the smaller confidence of the two points it averages, so each
// pixel the smallest confidence of the vertices its disparity depends on.
// The same two cases are left to the triangles (src/interp/interpolate_state.hpp).
#pragma once

#include <cstdint>

#include "src/interp/interpolate_state.hpp"
#include "src/kernels/kernel_set.hpp"
#include "src/tritree/tritree.hpp"
#include "tristereo/image.hpp"
#include "tristereo/mesh.hpp"

namespace tristereo {

// Scratch of one row of tiles of an image up to max_width wide: its grid
// values, S + 1 rows of at most max_width points, S more and one before,
// int32.
inline std::size_t midpoint_band_values(int tile_side, int max_width) {
  return static_cast<std::size_t>(tile_side + 1) * static_cast<std::size_t>(max_width) +
         static_cast<std::size_t>(tile_side) + 1;
}

// The same with the confidence maps: the values, then a byte per point (in
// int32 units, rounded up).
inline std::size_t midpoint_band_values_with_confidence(int tile_side, int max_width) {
  const std::size_t n = midpoint_band_values(tile_side, max_width);
  return n + (n + 3) / 4;
}

// Fractional bits of the grid values beyond Q4: log2 of the largest leaf's area2.
inline int midpoint_fraction_bits(int tile_side) { return 2 * __builtin_ctz(static_cast<unsigned>(tile_side)) - 1; }

// The tiles of rows [tile_row_begin, tile_row_end) of the grid: writes every
// pixel of those tiles that is a virtual grid point (each tile its half-open
// square, plus the grid's last column and row), from the vertices (`mesh`, the
// build's output) and their disparities (vertex_disp_q4[id]; an invalid one
// reads as a value like any other: invalidate_triangles() overwrites what it
// reaches). `scratch` holds midpoint_band_values(S, width) int32; the side-2
// level and the rounding are `kernels`' midpoints_row_q4. Disjoint tile rows
// write disjoint pixels. Returns true when some vertex it read was invalid
// (every vertex lies in some tile, so the tiles of all rows together say
// whether invalidate_triangles() is needed). Precondition: grid.need !=
// nullptr (not a 2-pixel strip). With `conf`, the same pixels of its maps
// too, in the same pass (`kernels`' midpoints_row_conf_q4), and scratch
// holds midpoint_band_values_with_confidence(S, width).
bool interpolate_midpoint_tiles(const TritreeGrid& grid, const Mesh& mesh, const std::int16_t* vertex_disp_q4,
                                int tile_row_begin, int tile_row_end, const KernelSet& kernels,
                                std::int32_t* scratch, ImageView<std::int16_t> disp_q4,
                                const ConfidenceMaps* conf = nullptr);

// After every tile: the stretched leaves [leaf_begin, leaf_end) of
// grid.stretched, by their planes (and their pixels' confidence by
// confidence_triangle). A leaf writes only the pixels it owns, so disjoint
// ranges may run at once, on different workers.
void interpolate_stretched_leaves(const TritreeGrid& grid, const Mesh& mesh,
                                  const std::int16_t* vertex_disp_q4, std::size_t leaf_begin,
                                  std::size_t leaf_end, ImageView<std::int16_t> disp_q4,
                                  const ConfidenceMaps* conf = nullptr);

// Then, when some vertex is invalid: every pixel owned by a triangle of
// [tri_begin, tri_end) with an invalid vertex becomes kInvalidDispQ4 (and
// confidence and state 0).
void invalidate_triangles(const Mesh& mesh, const std::int16_t* vertex_disp_q4, int tri_begin,
                          int tri_end, ImageView<std::int16_t> disp_q4, const ConfidenceMaps* conf = nullptr);

}  // namespace tristereo
