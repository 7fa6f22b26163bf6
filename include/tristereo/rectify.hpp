// Rectification as a pipeline stage: the inverse maps of a rig, computed once
// in double precision and stored in fixed point, then every frame remapped
// with integer bilinear weights (docs/calibration.md, "The fixed-point map").
//
//   StereoRig rig = read_rig("calib.yml");
//   auto maps = std::make_shared<RectifyMaps>(build_rectify_maps(rig, rectify_rig(rig)));
//   config.rectify = maps;               // Pipeline::process() now takes raw frames
//
// The fixed-point form, per rectified pixel (u, v) of each camera: (x, y) =
// raw_position(u, v) (rig.hpp), X = round(32 x), Y = round(32 y) (to nearest,
// ties to even, as OpenCV's maps), i.e. 1/32-pixel steps; then
//   ix = X >> 5, iy = Y >> 5 (floor), fx = X & 31, fy = Y & 31,
//   out = (p(ix, iy) (32 - fx)(32 - fy) + p(ix + 1, iy) fx (32 - fy)
//          + p(ix, iy + 1) (32 - fx) fy + p(ix + 1, iy + 1) fx fy + 512) >> 10
// with p = 0 outside the raw image (a non-finite position gives 0). The sum is
// at most 255 * 1024 < 2^18: 32-bit arithmetic never overflows. This is
// OpenCV's INTER_LINEAR fixed-point remap with BORDER_CONSTANT 0.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "tristereo/export.hpp"
#include "tristereo/image.hpp"
#include "tristereo/kernels.hpp"
#include "tristereo/rig.hpp"

namespace tristereo {

// 1/32 px: the map's fraction bits, and the weights' sum 32 * 32 = 1024.
constexpr int kRemapFracBits = 5;
constexpr int kRemapWeightBits = 2 * kRemapFracBits;

struct TRISTEREO_API RectifyMap {
  int width = 0, height = 0;          // rectified size
  int raw_width = 0, raw_height = 0;  // the camera's raw size
  // Pixels whose four taps are inside the raw image: xy[2 i], xy[2 i + 1] =
  // ix, iy and frac[i] = fy << 5 | fx (i = v * width + u). Other pixels hold
  // (0, 0, 0) here and are listed in `border`.
  std::vector<std::int16_t> xy;
  std::vector<std::uint16_t> frac;
  // Pixels with a tap outside (or no position): computed tap by tap with
  // p = 0 outside. ix, iy are clamped to [-2, raw side] (further out every
  // tap is outside anyway). Sorted by (v, u); border_row[v] .. border_row[v+1]
  // are row v's.
  struct Border {
    std::int32_t u;
    std::int16_t ix, iy;
    std::uint16_t frac;
  };
  std::vector<Border> border;
  std::vector<std::int32_t> border_row;
  std::size_t memory_bytes() const;
};

struct TRISTEREO_API RectifyMaps {
  RectifyMap left, right;
  Rectification rect;
  std::size_t memory_bytes() const;  // both maps
};

// Throws Error(kInvalidArgument) when the rig's images are larger than
// kMaxImageSide (the pipeline's limit, which keeps ix, iy in int16).
TRISTEREO_API RectifyMaps build_rectify_maps(const StereoRig& rig, const Rectification& rect);

// One camera's rectified image from its raw gray image (of the map's raw
// size), with the kernel set `kernels` (kAuto: the best this CPU runs). For
// tools and tests; the pipeline runs the same code on its workers.
TRISTEREO_API void remap_image(const RectifyMap& map, ImageView<const std::uint8_t> raw, ImageView<std::uint8_t> out,
                               KernelChoice kernels = KernelChoice::kAuto);

}  // namespace tristereo
