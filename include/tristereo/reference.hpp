// The float reference: the model of docs/model.md transcribed plainly (double
// arithmetic, Eigen for plane geometry, one thread, no SIMD, no fixed-point
// tricks). It is the specification in code; the integer Pipeline must equal it
// bit for bit. Slow by design; allocates freely.
#pragma once

#include "tristereo/export.hpp"

#include "tristereo/image.hpp"
#include "tristereo/mesh.hpp"
#include "tristereo/params.hpp"
#include "tristereo/rig.hpp"

namespace tristereo {

// left/right: 8-bit, 1 or 3 channels (converted to gray by the BT.601 rule).
// Throws Error on bad input, like Pipeline::process.
TRISTEREO_API StereoOutput run_reference(const ImageU8& left, const ImageU8& right, const StereoParams& params);

// The rectification of one camera's raw gray image (camera 0 left, 1 right),
// as include/tristereo/rectify.hpp defines it: raw_position() rounded to
// 1/32 px, bilinear weights in double, taps outside the image 0, rounded half
// up. The integer stage (fixed-point maps, integer weights) must equal it.
TRISTEREO_API ImageU8 reference_rectify(const StereoRig& rig, const Rectification& rect, int camera,
                                        const ImageU8& raw_gray);

}  // namespace tristereo
