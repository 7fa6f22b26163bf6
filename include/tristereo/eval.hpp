// Middlebury (v2) style evaluation of disparity maps.
#pragma once

#include "tristereo/export.hpp"

#include <cstdint>
#include <string>
#include <vector>

#include "tristereo/image.hpp"
#include "tristereo/mesh.hpp"

namespace tristereo {

struct BadPixelStats {
  double bad_0_5 = 0, bad_1 = 0, bad_2 = 0;  // percent of evaluated pixels with error > t
  std::int64_t evaluated = 0;  // pixels with known ground truth inside the mask
  std::int64_t invalid = 0;    // evaluated pixels without a disparity (counted as bad)
  double rms = 0;              // RMS error (px) over evaluated pixels that have a disparity
};

// disp: pixels, +inf or NaN = no disparity. gt: pixels, 0 or non-finite =
// unknown (skipped). mask: empty (null data) = every known pixel, else a pixel
// counts when mask == 255. A pixel is bad at t when it has no disparity or
// |d - gt| > t. With nothing evaluated every field is 0.
// Throws kSizeMismatch / kInvalidArgument / kUnsupportedFormat (channels != 1).
TRISTEREO_API BadPixelStats evaluate_disparity(ImageView<const float> disp, ImageView<const float> gt,
                                 ImageView<const std::uint8_t> mask);

// The same statistics at sample positions only (e.g. the mesh vertices and
// their sparse disparities, Q4 with kInvalidDispQ4 = none). Points outside gt
// throw kInvalidArgument.
TRISTEREO_API BadPixelStats evaluate_at_points(ImageView<const float> gt, const std::vector<Vertex>& pts,
                                 const std::vector<std::int16_t>& disp_q4,
                                 ImageView<const std::uint8_t> mask);

// A Middlebury 8-bit ground-truth PNG: disparity = value / gt_scale, 0 stays 0
// (unknown). gt_scale in 1..255; the PNG must be single-channel.
TRISTEREO_API Image<float> load_middlebury_gt(const std::string& png_path, int gt_scale);

struct MiddleburyScene {
  std::string name;
  int width = 0, height = 0, ndisp = 0, gt_scale = 0;
};

// Reads datasets.tsv (tab-separated, header row naming at least the columns
// name, width, height, ndisp, gt_scale, in any order). kIoError if missing,
// kCorruptFile for a malformed row or missing column.
TRISTEREO_API std::vector<MiddleburyScene> read_datasets_tsv(const std::string& path);

}  // namespace tristereo
