// The tritree mesh and the outputs of one frame.
//
// Canonical order (identical in the integer path and the float reference, so
// outputs compare with ==):
//  - vertices sorted by (y, x): vertex ids are raster order, and the vertices
//    of row y are the contiguous range [row_start[y], row_start[y + 1]);
//  - each triangle lists its vertex ids with positive orientation
//    ((b - a) x (c - a) > 0 in pixel coordinates, x right, y down), rotated so
//    the smallest id comes first;
//  - triangles in the hierarchy's order (docs/model.md section 1, "Output
//    order"): tiles in raster order, and in each tile its two halves, each
//    read depth first, a split triangle's child (C, A, m) before (B, C, m).
//    The mesher emits them in that order, so no sort is needed; sort a copy
//    if you want them lexicographically.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "tristereo/image.hpp"

namespace tristereo {

struct Vertex {
  std::int32_t x = 0;
  std::int32_t y = 0;
  bool operator==(const Vertex& o) const { return x == o.x && y == o.y; }
};

using Triangle = std::array<std::int32_t, 3>;

struct Mesh {
  int width = 0;
  int height = 0;
  std::vector<Vertex> vertices;
  std::vector<Triangle> triangles;
  std::vector<std::int32_t> row_start;  // height + 1 entries
  std::int64_t forced_splits = 0;       // splits done only to keep the mesh conforming
  std::int64_t criterion_splits = 0;    // splits the criterion asked for

  bool operator==(const Mesh& o) const {
    return width == o.width && height == o.height && vertices == o.vertices &&
           triangles == o.triangles && row_start == o.row_start &&
           forced_splits == o.forced_splits && criterion_splits == o.criterion_splits;
  }
};

// What the validity stage (docs/model.md section 6) did to the samples:
// samples are the mesh vertices (sparse) or the pixels (dense mode).
struct SampleValidity {
  std::int32_t samples = 0;               // samples matched
  std::int32_t uniqueness_rejected = 0;   // failed the uniqueness test
  std::int32_t lr_rejected = 0;           // failed the left-right check
  std::int32_t filled = 0;                // invalid samples given a neighbour's disparity
  bool operator==(const SampleValidity& o) const {
    return samples == o.samples && uniqueness_rejected == o.uniqueness_rejected &&
           lr_rejected == o.lr_rejected && filled == o.filled;
  }
};

// Everything one frame produces.
struct StereoOutput {
  Mesh mesh;
  std::vector<std::int16_t> vertex_disp_q4;  // one per mesh vertex, kInvalidDispQ4 = invalid
  ImageS16 disp_q4;                          // dense map, kInvalidDispQ4 = invalid
  SampleValidity validity;
};

}  // namespace tristereo
