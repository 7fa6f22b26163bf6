// The float reference: the model of docs/model.md transcribed plainly (double
// arithmetic, Eigen for plane geometry, one thread, no SIMD, no fixed-point
// tricks). It is the specification in code; the integer Pipeline must equal it
// bit for bit. Slow by design; allocates freely.
#pragma once

#include "tristereo/export.hpp"

#include "tristereo/image.hpp"
#include "tristereo/mesh.hpp"
#include "tristereo/params.hpp"

namespace tristereo {

// left/right: 8-bit, 1 or 3 channels (converted to gray by the BT.601 rule).
// Throws Error on bad input, like Pipeline::process.
TRISTEREO_API StereoOutput run_reference(const ImageU8& left, const ImageU8& right, const StereoParams& params);

}  // namespace tristereo
