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
  // Measured or filled samples below StereoParams::validity.min_confidence,
  // made invalid after the fill.
  std::int32_t min_confidence_rejected = 0;
  // Support prior (StereoParams::prior, docs/model.md section 6b): samples
  // whose winner was chosen again, those of them its uniqueness test made
  // invalid (for the fill), the invalid ones it gave a disparity (recovered)
  // and the valid ones it made invalid (lost). Before the fill,
  // uniqueness_rejected + lr_rejected - prior_recovered + prior_lost samples
  // are invalid.
  std::int32_t prior_redecided = 0;
  std::int32_t prior_rejected = 0;
  std::int32_t prior_recovered = 0;
  std::int32_t prior_lost = 0;
  bool operator==(const SampleValidity& o) const {
    return samples == o.samples && uniqueness_rejected == o.uniqueness_rejected &&
           lr_rejected == o.lr_rejected && filled == o.filled &&
           min_confidence_rejected == o.min_confidence_rejected && prior_redecided == o.prior_redecided &&
           prior_rejected == o.prior_rejected && prior_recovered == o.prior_recovered && prior_lost == o.prior_lost;
  }
};

// Where a sample's or a pixel's disparity comes from (docs/model.md section 7).
// The values are those of the state maps and of `tristereo match --valid`.
enum class SampleState : std::uint8_t {
  kInvalid = 0,   // no disparity (kInvalidDispQ4)
  kFilled = 1,    // a neighbour's disparity, given by the fill
  kMeasured = 2,  // matched, and passed the uniqueness test and the left-right check (or
                  // chosen again by the support prior and passed its uniqueness test)
};

// Confidence, 0..255 (docs/model.md section 7): 0 = invalid, 1..127 = filled
// (lower the more fill rounds away from a measured sample), 128..255 =
// measured (higher the larger the margin between the best summed cost and
// the best one two or more disparities away). So the state follows from it.
constexpr int kMinMeasuredConfidence = 128;

// Everything one frame produces.
struct StereoOutput {
  Mesh mesh;
  std::vector<std::int16_t> vertex_disp_q4;  // one per mesh vertex, kInvalidDispQ4 = invalid
  ImageS16 disp_q4;                          // dense map, kInvalidDispQ4 = invalid
  // Per mesh vertex, like vertex_disp_q4: a SampleState value and the confidence.
  std::vector<std::uint8_t> vertex_state;
  std::vector<std::uint8_t> vertex_confidence;
  // Per pixel, like disp_q4: the smallest state and confidence of the vertices
  // the pixel's disparity is interpolated from (its triangle's three inside
  // it, an edge's two ends on that edge, a vertex's own; 0 when the disparity
  // is invalid); dense mode: the pixel's own.
  ImageU8 pixel_state;
  ImageU8 pixel_confidence;
  SampleValidity validity;
};

}  // namespace tristereo
