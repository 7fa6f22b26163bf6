// Lens models and the rectified-to-raw projection, in double precision
// (src/rectify/rectify_geometry.cpp; public entry points in tristereo/rig.hpp).
#pragma once

#include "tristereo/rig.hpp"

namespace tristereo {

// atan and tan from +, -, *, / and sqrt only: the same bits on every platform.
double rectify_atan(double x);
double rectify_tan(double t);  // |t| < pi/2

// Normalised undistorted (x, y) -> distorted, and back by `iterations` steps.
void lens_distort(const RawCamera& cam, double x, double y, double* xd, double* yd);
void lens_undistort(const RawCamera& cam, double xd, double yd, int iterations, double* x, double* y);

// raw_position() of one camera with the back-projection (P[:, 0:3] R)^-1
// computed once: the map builders call raw() for every rectified pixel.
class RectifyProjector {
 public:
  RectifyProjector(const StereoRig& rig, const Rectification& rect, int camera);
  // NaN when the ray does not reach the front of the camera.
  void raw(double u, double v, double* x, double* y) const;

 private:
  RawCamera cam_;
  double m_[9];
};

}  // namespace tristereo
