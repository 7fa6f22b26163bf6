// The samples of a frame and their neighbourhood: the tritree mesh's vertices
// (sparse mode) or every pixel (dense mode, the paper's baseline).
#pragma once

#include <cstdint>

#include "tristereo/mesh.hpp"

namespace tristereo {

// Samples are numbered in raster order in both modes: mesh vertex ids (sorted
// by (y, x), docs/model.md section 1) or y * width + x.
struct SampleLayout {
  const Mesh* mesh = nullptr;  // null = dense: every pixel of width x height
  int width = 0;
  int height = 0;

  bool dense() const { return mesh == nullptr; }
  int count() const {
    return dense() ? width * height : static_cast<int>(mesh->vertices.size());
  }
  int row_begin(int y) const {
    return dense() ? y * width : mesh->row_start[static_cast<std::size_t>(y)];
  }
  int row_end(int y) const { return row_begin(y + 1); }
  int x_of(int i) const {
    return dense() ? i % width : mesh->vertices[static_cast<std::size_t>(i)].x;
  }
  int y_of(int i) const {
    return dense() ? i / width : mesh->vertices[static_cast<std::size_t>(i)].y;
  }
};

// Path directions (docs/model.md section 3b): the step u a path takes from a
// sample's predecessor towards it. The first four are used with 4 directions.
// Even directions run forward (raster order), odd ones backward.
struct PathDirection {
  int dx, dy;
};
constexpr PathDirection kPathDirections[8] = {{1, 0},  {-1, 0}, {0, 1},  {0, -1},
                                              {1, 1},  {-1, -1}, {-1, 1}, {1, -1}};
inline bool path_runs_forward(int r) { return (r & 1) == 0; }

// Candidate q (offset p - q = (dx, dy)) follows direction u better than the
// current best (bdx, bdy) when its cosine with u is larger (exact: compare
// dot^2 / len^2 by cross-multiplication); dot > 0 for both.
inline bool follows_better(int dx, int dy, int bdx, int bdy, PathDirection u) {
  const std::int64_t dot = std::int64_t{dx} * u.dx + std::int64_t{dy} * u.dy;
  const std::int64_t bdot = std::int64_t{bdx} * u.dx + std::int64_t{bdy} * u.dy;
  const std::int64_t len = std::int64_t{dx} * dx + std::int64_t{dy} * dy;
  const std::int64_t blen = std::int64_t{bdx} * bdx + std::int64_t{bdy} * bdy;
  return dot * dot * blen > bdot * bdot * len;
}

}  // namespace tristereo
