// Evaluation of disparity maps against ground truth: bad-pixel rates at
// 0.5 / 1 / 2 / 3 px and KITTI's D1, the ground-truth file formats of the
// public data sets (Middlebury v2 and 2014, KITTI 2015, ETH3D), and the checks
// that catch a wrong scale or swapped files before a score misleads anyone.
#pragma once

#include "tristereo/export.hpp"

#include <cstdint>
#include <string>
#include <vector>

#include "tristereo/image.hpp"
#include "tristereo/mesh.hpp"

namespace tristereo {

// Percentages of the evaluated pixels. A pixel is bad at t when it has no
// disparity (invalid counts as bad, as in every benchmark we compare with) or
// when |d - gt| > t. D1 is KITTI 2015's outlier rate: |d - gt| > 3 px AND
// |d - gt| > 5 % of gt (or no disparity).
struct BadPixelStats {
  double bad_0_5 = 0, bad_1 = 0, bad_2 = 0, bad_3 = 0;
  double d1 = 0;
  std::int64_t evaluated = 0;  // pixels with known ground truth inside the mask
  std::int64_t invalid = 0;    // evaluated pixels without a disparity (counted as bad)
  double rms = 0;              // RMS error (px) over evaluated pixels that have a disparity
  // End-point error: the mean |d - gt| (px) over the evaluated pixels that
  // have a disparity (invalid ones are not in it: `invalid` says how many).
  double epe = 0;
};

// disp: pixels, +inf or NaN = no disparity. gt: pixels, 0 or non-finite =
// unknown (skipped). mask: empty (null data) = every known pixel, else a pixel
// counts when mask == 255 (Middlebury v2 nonocc.png; Middlebury 2014
// mask0nocc.png, where 128 = occluded and 0 = no ground truth, so 255 selects
// the non-occluded known pixels). With nothing evaluated every field is 0.
// Throws kSizeMismatch / kInvalidArgument / kUnsupportedFormat (channels != 1).
TRISTEREO_API BadPixelStats evaluate_disparity(ImageView<const float> disp, ImageView<const float> gt,
                                 ImageView<const std::uint8_t> mask);

// The same statistics at sample positions only (e.g. the mesh vertices and
// their sparse disparities, Q4 with kInvalidDispQ4 = none). Points outside gt
// throw kInvalidArgument.
TRISTEREO_API BadPixelStats evaluate_at_points(ImageView<const float> gt, const std::vector<Vertex>& pts,
                                 const std::vector<std::int16_t>& disp_q4,
                                 ImageView<const std::uint8_t> mask);

// ---------------------------------------------------------------- disparity files
// The encodings a disparity map or a ground truth comes in:
//  kPfm    float PFM in pixels; +inf (any non-finite) = none (Middlebury 2014, ETH3D, match --disp X.pfm)
//  kPng8   8-bit gray PNG, d = value / scale; 0 stays 0, which in a ground truth
//          means unknown (Middlebury v2 disp_left.png with its gt_scale)
//  kQ4     16-bit gray PNG, d = value / 16, 0 = none (match --disp X.png)
//  kKitti  16-bit gray PNG, d = value / 256, 0 = none (KITTI disp_occ_0.png,
//          match --disp X.png --disp-format kitti)
enum class DispFileFormat { kPfm, kPng8, kQ4, kKitti };

TRISTEREO_API const char* to_string(DispFileFormat f);  // "pfm", "png8", "q4", "kitti"
// "pfm", "png8", "q4", "kitti" -> the format; false for anything else.
TRISTEREO_API bool parse_disp_file_format(const std::string& name, DispFileFormat* out);

// The format from the file's first bytes: PFM ("Pf"/"PF"), an 8-bit PNG ->
// kPng8, a 16-bit PNG -> png16 (a 16-bit PNG does not say whether it is Q4 or
// KITTI; the caller knows which is likelier). kIoError if unreadable,
// kUnsupportedFormat for anything else.
TRISTEREO_API DispFileFormat detect_disp_file_format(const std::string& path, DispFileFormat png16);

// Reads a disparity map or ground truth as float pixels, +inf where the file
// holds none (kPfm: any non-finite; kQ4/kKitti: 0); kPng8 keeps 0 as 0 and
// divides by png8_scale (1..255, else kInvalidArgument). The values are exact:
// value / 16 and value / 256 are representable in float. A file that does not
// hold `format` (a PFM read as PNG, an 8-bit PNG read as kQ4, a colour image,
// a 3-channel PFM) -> kUnsupportedFormat naming what the file holds.
TRISTEREO_API Image<float> read_disparity_px(const std::string& path, DispFileFormat format, int png8_scale);

// A Middlebury 8-bit ground-truth PNG: read_disparity_px(path, kPng8, gt_scale).
TRISTEREO_API Image<float> load_middlebury_gt(const std::string& png_path, int gt_scale);

// ---------------------------------------------------------------- sanity checks
// What a caller needs to warn that a score is probably meaningless rather than
// bad: from the two maps alone, before any threshold.
struct EvalInputCheck {
  std::int64_t pixels = 0;
  std::int64_t disp_none = 0;    // DISP pixels without a disparity (non-finite)
  std::int64_t gt_unknown = 0;   // GT pixels unknown (0 or non-finite)
  // Known values that are not multiples of 1/16 px: a fixed-point matcher's
  // output (tristereo, OpenCV) has none; a float ground truth (Middlebury
  // 2014, ETH3D) or KITTI's value / 256 has many.
  std::int64_t disp_off_q4_grid = 0, gt_off_q4_grid = 0;
  std::int64_t both = 0;         // pixels where both are known and positive
  // Median over `both` of gt / disp: about 1 when the scales agree; about k
  // when the ground truth is stored k times the disparity and read unscaled.
  double median_gt_over_disp = 0;  // 0 when `both` is empty
};
TRISTEREO_API EvalInputCheck check_eval_inputs(ImageView<const float> disp, ImageView<const float> gt);

// The scales disagree: the median ratio is outside [2/3, 3/2] (a wrong
// integer scale is at least a factor 2; a bad matcher seldom biases every
// pixel by half).
TRISTEREO_API bool scale_looks_wrong(const EvalInputCheck& c);
// DISP and GT look swapped: the "ground truth" looks like a fixed-point
// matcher's output (every known value on the 1/16 px grid, and at least ten
// times fewer holes than DISP) while the "disparity map" looks like ground
// truth (holes at 0.1 % of the pixels or more, as structured light and LiDAR
// leave, and 10 % or more of its values off the 1/16 grid). Each signal alone
// has innocent causes (a complete v2 ground truth, a matcher that leaves
// occlusions invalid, a float-output matcher); together they do not.
TRISTEREO_API bool files_look_swapped(const EvalInputCheck& c);

// ---------------------------------------------------------------- datasets.tsv
struct MiddleburyScene {
  std::string name;
  int width = 0, height = 0, ndisp = 0, gt_scale = 0;
  // Optional columns (empty when the file has none, e.g. the v2 set):
  std::string gt_file;    // ground truth file name inside the scene folder
  std::string gt_format;  // "pfm" or "kitti16"
  std::string noc_mask;   // non-occluded mask file name, or "none"
};

// Reads datasets.tsv (tab-separated, header row naming at least the columns
// name, width, height, ndisp, gt_scale, in any order; gt_file, gt_format and
// noc_mask when present). kIoError if missing, kCorruptFile for a malformed
// row or missing column.
TRISTEREO_API std::vector<MiddleburyScene> read_datasets_tsv(const std::string& path);

}  // namespace tristereo
