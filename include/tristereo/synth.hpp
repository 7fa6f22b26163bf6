// Synthetic stereo scenes with exact ground truth.
//
// A scene is a list of textured planar surfaces described in left-image
// coordinates. Both views are rendered from that description (never by
// warping one image): right pixel xr on row y shows, among all surfaces, the
// point at left coordinate xl with xl - d(xl, y) = xr of largest disparity
// (nearest). Each surface's texture is a function of its own coordinates
// (integer lattice + linear interpolation along x in Q16), so
//  - fronto-parallel surfaces (integer disparity) give exact equality
//    left(x, y) == right(x - d, y) wherever the point is visible in both views;
//  - slanted surfaces have exact float ground truth (disparity in Q16, exactly
//    representable in float for d < 256).
// Everything is integer arithmetic and a fixed PRNG (splitmix64), so a scene
// is identical for a given seed on every compiler and platform.
#pragma once

#include "tristereo/export.hpp"

#include <cstdint>

#include "tristereo/image.hpp"

namespace tristereo {

struct SyntheticScene {
  ImageU8 left, right;      // gray
  Image<float> disp_left;   // exact disparity of every left pixel, pixels
  ImageU8 nonocc_mask;      // 255: the left pixel's point is visible in the right view
};

struct SynthParams {
  int width = 640, height = 480;  // 16 .. 4096 each
  int num_disp = 64;              // 8 .. 256; all disparities lie in [1, num_disp - 1]
  std::uint32_t seed = 1;
  int frame = 0;                  // moving sequences: objects shift by a per-object velocity
};

// A slanted textured background, five fronto-parallel rectangles and discs at
// integer disparities occluding each other and the background, and one slanted
// rectangle. Disparities are >= 1, so evaluators that treat 0 as "unknown" see
// every pixel. Throws Error(kInvalidArgument) for parameters out of range.
TRISTEREO_API SyntheticScene make_synthetic_scene(const SynthParams& params);

// One fronto-parallel textured plane at integer disparity `disp` (0 .. w - 1)
// everywhere: right(x - disp, y) == left(x, y). Left columns x < disp have no
// match and are 0 in nonocc_mask. w, h in 2..4096.
TRISTEREO_API SyntheticScene make_planar_scene(int w, int h, int disp, std::uint32_t seed);

}  // namespace tristereo
