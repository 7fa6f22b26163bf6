// Metric depth from a disparity map and a calibration (calib.hpp).
//
// For a pixel with disparity d = disp_q4 / 16 (pixels):
//   Z = focal_px * baseline_m / (d + doffs_px)      metres, along the optical axis
//   X = (x - cx_px) Z / focal_px, Y = (y - cy_px) Z / focal_px   (camera frame, y down)
// A pixel is invalid (no depth) when its disparity is kInvalidDispQ4 or
// d + doffs_px <= 0 (a point at or beyond infinity).
#pragma once

#include <cstdint>
#include <string>

#include "tristereo/calib.hpp"
#include "tristereo/export.hpp"
#include "tristereo/image.hpp"

namespace tristereo {

// Depth in metres, +infinity where invalid. Throws kInvalidArgument on a
// multi-channel map or a camera with focal length or baseline <= 0.
TRISTEREO_API Image<float> depth_m_from_disp_q4(ImageView<const std::int16_t> disp_q4,
                                               const CameraParams& camera);

// The same from float disparities in pixels (e.g. a ground-truth PFM);
// a non-finite disparity is invalid.
TRISTEREO_API Image<float> depth_m_from_disp_px(ImageView<const float> disp_px, const CameraParams& camera);

// Which disparities the metric outputs keep (depth, point cloud, metric mesh).
// Depth error grows as Z^2: a disparity error of e px moves Z by about
// Z * e / (d + doffs), so a half-pixel error at an effective disparity of 2 px
// is already a quarter of Z. Points beyond that are the rig's far field,
// left out unless asked for (min_disparity_px = 0).
struct DepthLimits {
  double min_disparity_px = 2.0;  // keep d + doffs_px >= this (pixels); 0 = every d + doffs > 0
  double min_depth_m = 0;         // keep Z >= this; 0 = no lower limit
  double max_depth_m = 0;         // keep Z <= this; 0 = no upper limit
};
// kInvalidArgument unless every limit is finite and >= 0, and max_depth_m is
// 0 or above min_depth_m. The message names the field.
TRISTEREO_API void check_depth_limits(const DepthLimits& limits);
// Sets kInvalidDispQ4 wherever the limits exclude the disparity (the rest is
// untouched) and returns how many values it invalidated. Works on a dense map
// (one channel) or a row of vertex disparities (height 1). The test is exact:
// d + doffs and Z = f B / (d + doffs) in double, as depth_m_from_disp_q4 does.
TRISTEREO_API std::int64_t apply_depth_limits(ImageView<std::int16_t> disp_q4, const CameraParams& camera,
                                             const DepthLimits& limits);

// What write_depth wrote.
struct DepthWriteReport {
  std::int64_t valid = 0;         // pixels with a depth in the file
  std::int64_t invalid = 0;       // pixels without (+inf in PFM, 0 in PNG)
  std::int64_t out_of_range = 0;  // PNG only: depth >= 65.535 m, written as 0
};

// By extension: .pfm = float metres (Middlebury PFM, +inf = invalid);
// .png = uint16 millimetres, rounded to nearest, 0 = invalid (the ROS depth
// image convention; depths of 65.535 m and more cannot be stored and are
// written as 0 and counted). Other extensions: kInvalidArgument.
TRISTEREO_API DepthWriteReport write_depth(const std::string& path, ImageView<const float> depth_m);

// The dense map as a coloured point cloud: one PLY vertex (float x, y, z in
// metres + uchar red, green, blue from the left image) per valid pixel, no
// faces; binary little endian or ASCII. Returns the number of points.
// kInvalidArgument (and no file) when the camera puts a point beyond float
// range: inf/nan coordinates are never written.
TRISTEREO_API std::int64_t write_points_ply(const std::string& path, ImageView<const std::int16_t> disp_q4,
                                           ImageView<const std::uint8_t> left_gray_or_rgb,
                                           const CameraParams& camera, bool binary);

}  // namespace tristereo
