// The rectification as the model defines it (include/tristereo/rectify.hpp),
// written plainly: for each rectified pixel, the raw position in double (the
// one definition, raw_position), rounded to 1/32 px, and a bilinear blend of
// the four raw pixels with weights in double. Every quantity is a multiple of
// 1/1024 below 2^18, so double holds it exactly and the integer path's
// (sum + 512) >> 10 is floor(value + 1/2) here.
#include <cmath>

#include "src/rectify/rectify_geometry.hpp"
#include "tristereo/reference.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

ImageU8 reference_rectify(const StereoRig& rig, const Rectification& rect, int camera, const ImageU8& raw) {
  const RawCamera& cam = camera == 0 ? rig.left : rig.right;
  if (raw.channels != 1 || raw.width != cam.width || raw.height != cam.height)
    throw Error(ErrorCode::kSizeMismatch, "reference_rectify: the raw image must be gray and of the camera's size");
  const RectifyProjector projector(rig, rect, camera);
  auto p = [&](double x, double y) -> double {
    return x >= 0 && y >= 0 && x < raw.width && y < raw.height ? raw.at(static_cast<int>(x), static_cast<int>(y)) : 0.0;
  };
  ImageU8 out(rect.width, rect.height, 1);
  for (int v = 0; v < rect.height; ++v)
    for (int u = 0; u < rect.width; ++u) {
      double x, y;
      projector.raw(u, v, &x, &y);
      double value = 0;
      if (std::isfinite(x) && std::isfinite(y) && std::fabs(x) < 1e9 && std::fabs(y) < 1e9) {
        const double X = std::nearbyint(x * 32) / 32, Y = std::nearbyint(y * 32) / 32;  // the 1/32-px position
        const double ix = std::floor(X), iy = std::floor(Y);
        const double fx = X - ix, fy = Y - iy;
        value = p(ix, iy) * (1 - fx) * (1 - fy) + p(ix + 1, iy) * fx * (1 - fy) + p(ix, iy + 1) * (1 - fx) * fy +
                p(ix + 1, iy + 1) * fx * fy;
      }
      out.at(u, v) = static_cast<std::uint8_t>(std::floor(value + 0.5));
    }
  return out;
}

}  // namespace tristereo
