// The rig's geometry in double precision: lens models, the rectification
// (the construction of OpenCV's stereoRectify, CALIB_ZERO_DISPARITY, alpha 0)
// and the inverse map from a rectified pixel to a raw one.
//
// Compiled like the float reference (-ffp-contract=off, EIGEN_DONT_VECTORIZE,
// see CMakeLists.txt) and using no libm function but sqrt, which IEEE 754
// rounds exactly: the fixed-point maps round these values, so they must be the
// same numbers on every platform (x86's and ARM's libm may differ by an ulp in
// atan or tan, and an ulp can flip a rounding to 1/32 px).
#include <cmath>
#include <cstdio>

#include <Eigen/Dense>

#include "src/rectify/rectify_geometry.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

namespace {

using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;

constexpr double kHalfPi = 1.57079632679489661923;

Mat3 mat3(const std::array<double, 9>& a) {
  Mat3 m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = a[static_cast<std::size_t>(3 * i + j)];
  return m;
}

std::array<double, 9> arr9(const Mat3& m) {
  std::array<double, 9> a{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a[static_cast<std::size_t>(3 * i + j)] = m(i, j);
  return a;
}

// The rotation by the unit quaternion (w, x, y, z).
Mat3 from_quaternion(double w, double x, double y, double z) {
  Mat3 m;
  m << 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),  //
      2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),   //
      2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y);
  return m;
}

// The rotation by half the angle of R about the same axis: through the
// quaternion (w >= 0), whose half is normalise(1 + w, x, y, z) - sqrt only,
// no acos/sin/cos (Rodrigues' form would need them).
Mat3 half_rotation(const Mat3& R) {
  double w, x, y, z;
  const double tr = R.trace();
  if (tr > 0) {
    const double s = 2 * std::sqrt(1 + tr);
    w = s / 4;
    x = (R(2, 1) - R(1, 2)) / s;
    y = (R(0, 2) - R(2, 0)) / s;
    z = (R(1, 0) - R(0, 1)) / s;
  } else if (R(0, 0) >= R(1, 1) && R(0, 0) >= R(2, 2)) {
    const double s = 2 * std::sqrt(1 + R(0, 0) - R(1, 1) - R(2, 2));
    w = (R(2, 1) - R(1, 2)) / s;
    x = s / 4;
    y = (R(0, 1) + R(1, 0)) / s;
    z = (R(0, 2) + R(2, 0)) / s;
  } else if (R(1, 1) >= R(2, 2)) {
    const double s = 2 * std::sqrt(1 + R(1, 1) - R(0, 0) - R(2, 2));
    w = (R(0, 2) - R(2, 0)) / s;
    x = (R(0, 1) + R(1, 0)) / s;
    y = s / 4;
    z = (R(1, 2) + R(2, 1)) / s;
  } else {
    const double s = 2 * std::sqrt(1 + R(2, 2) - R(0, 0) - R(1, 1));
    w = (R(1, 0) - R(0, 1)) / s;
    x = (R(0, 2) + R(2, 0)) / s;
    y = (R(1, 2) + R(2, 1)) / s;
    z = s / 4;
  }
  if (w < 0) {
    w = -w;
    x = -x;
    y = -y;
    z = -z;
  }
  const double hw = 1 + w;
  const double n = std::sqrt(hw * hw + x * x + y * y + z * z);
  return from_quaternion(hw / n, x / n, y / n, z / n);
}

// sin and cos of |t| <= pi/2 from Taylor series on t / 8 and three doublings.
void sin_cos(double t, double* s, double* c) {
  const double h = t / 8;
  double term = h, sn = 0, cs = 0, cterm = 1;
  for (int k = 1; k <= 25; k += 2) {
    sn += term;
    term = -term * h * h / ((k + 1) * (k + 2));
  }
  for (int k = 0; k <= 24; k += 2) {
    cs += cterm;
    cterm = -cterm * h * h / ((k + 1) * (k + 2));
  }
  for (int i = 0; i < 3; ++i) {
    const double s2 = 2 * sn * cs, c2 = 1 - 2 * sn * sn;
    sn = s2;
    cs = c2;
  }
  *s = sn;
  *c = cs;
}

}  // namespace

double rectify_atan(double x) {
  if (x < 0) return -rectify_atan(-x);
  if (x > 1) return kHalfPi - rectify_atan(1 / x);
  // Two halvings, atan(x) = 2 atan(x / (1 + sqrt(1 + x^2))), bring x below
  // tan(pi/16) = 0.199, where 13 terms of the series are exact to 1e-19.
  for (int i = 0; i < 2; ++i) x = x / (1 + std::sqrt(1 + x * x));
  const double x2 = x * x;
  double sum = 0, p = x;
  for (int k = 0; k < 13; ++k) {
    sum += (k % 2 == 0 ? p : -p) / (2 * k + 1);
    p *= x2;
  }
  return 4 * sum;
}

double rectify_tan(double t) {
  double s, c;
  sin_cos(t, &s, &c);
  return s / c;
}

void lens_distort(const RawCamera& cam, double x, double y, double* xd, double* yd) {
  const std::array<double, 8>& k = cam.dist;
  if (cam.model == DistortionModel::kEquidistant) {
    const double r = std::sqrt(x * x + y * y);
    if (r == 0) {
      *xd = x;
      *yd = y;
      return;
    }
    const double th = rectify_atan(r), th2 = th * th;
    const double thd = th * (1 + th2 * (k[0] + th2 * (k[1] + th2 * (k[2] + th2 * k[3]))));
    *xd = x * (thd / r);
    *yd = y * (thd / r);
    return;
  }
  const double r2 = x * x + y * y;
  const double radial = (1 + r2 * (k[0] + r2 * (k[1] + r2 * k[4]))) / (1 + r2 * (k[5] + r2 * (k[6] + r2 * k[7])));
  *xd = x * radial + 2 * k[2] * x * y + k[3] * (r2 + 2 * x * x);
  *yd = y * radial + k[2] * (r2 + 2 * y * y) + 2 * k[3] * x * y;
}

void lens_undistort(const RawCamera& cam, double xd, double yd, int iterations, double* x, double* y) {
  const std::array<double, 8>& k = cam.dist;
  if (cam.model == DistortionModel::kEquidistant) {
    // Newton on theta (1 + k1 theta^2 + ...) = theta_d.
    const double thd = std::sqrt(xd * xd + yd * yd);
    double th = thd;
    for (int i = 0; i < iterations && thd > 0; ++i) {
      const double t2 = th * th;
      const double f = th * (1 + t2 * (k[0] + t2 * (k[1] + t2 * (k[2] + t2 * k[3])))) - thd;
      const double df = 1 + t2 * (3 * k[0] + t2 * (5 * k[1] + t2 * (7 * k[2] + t2 * 9 * k[3])));
      th -= f / df;
    }
    const double scale = thd > 0 && th < kHalfPi && th > 0 ? rectify_tan(th) / thd : 1;
    *x = xd * scale;
    *y = yd * scale;
    return;
  }
  // OpenCV's fixed-point iteration (undistortPoints): x = (x_d - tangential(x)) / radial(x).
  double ux = xd, uy = yd;
  for (int i = 0; i < iterations; ++i) {
    const double r2 = ux * ux + uy * uy;
    const double inv = (1 + r2 * (k[5] + r2 * (k[6] + r2 * k[7]))) / (1 + r2 * (k[0] + r2 * (k[1] + r2 * k[4])));
    if (inv < 0) {
      ux = xd;
      uy = yd;
      break;
    }
    const double dx = 2 * k[2] * ux * uy + k[3] * (r2 + 2 * ux * ux);
    const double dy = k[2] * (r2 + 2 * uy * uy) + 2 * k[3] * ux * uy;
    ux = (xd - dx) * inv;
    uy = (yd - dy) * inv;
  }
  *x = ux;
  *y = uy;
}

namespace {

// Normalised undistorted coordinates of raw pixel (u, v).
void normalised(const RawCamera& cam, double u, double v, int iterations, double* x, double* y) {
  const std::array<double, 9>& K = cam.K;
  const double yd = (v - K[5]) / K[4];
  const double xd = (u - K[2] - K[1] * yd) / K[0];
  lens_undistort(cam, xd, yd, iterations, x, y);
}

// OpenCV's stereoRectify undistorts the corners and the border grid with
// undistortPoints' default of 5 iterations; using the same count keeps f and
// the principal point within 3e-5 px of cv2's (docs/calibration.md).
constexpr int kRectifyIterations = 5;
// The border grid of the largest-rectangle search: 9 x 9 points from 0 to W
// and H (OpenCV's grid, which ends one pixel past the last pixel centre).
constexpr int kGrid = 9;

[[noreturn]] void refuse(const std::string& path, const std::string& what) {
  throw Error(ErrorCode::kInvalidArgument, "calibration file '" + path + "': " + what);
}

}  // namespace

Rectification compute_rectification(const StereoRig& rig) {
  const int W = rig.left.width, H = rig.left.height;
  const Mat3 R = mat3(rig.R);
  const Vec3 T(rig.T[0], rig.T[1], rig.T[2]);
  // Both cameras turn half of R towards each other: rr takes the right
  // camera's frame to the common orientation, rr^T the left one's.
  const Mat3 rr = half_rotation(R).transpose();
  const Vec3 t = rr * T;
  if (!(std::fabs(t(0)) > std::fabs(t(1))))
    refuse(rig.path, "the cameras are not side by side (after the common rotation the baseline is more vertical "
                     "than horizontal); a vertical rig is not supported");
  if (!(t(0) < 0))
    refuse(rig.path, "the right camera is to the left of the left one (T's x > 0 after the common rotation): "
                     "left and right swapped?");
  // Then both turn so that the baseline lies along x: the rotation taking
  // t / |t| to (-1, 0, 0) about their common normal.
  const Vec3 a = t / t.norm(), b(-1, 0, 0);
  const Vec3 axis = a.cross(b);
  const double s = axis.norm(), c = a.dot(b);
  Mat3 align = Mat3::Identity();
  if (s > 0) {
    const Vec3 k = axis / s;
    Mat3 kx;
    kx << 0, -k(2), k(1), k(2), 0, -k(0), -k(1), k(0), 0;
    align = Mat3::Identity() + s * kx + (1 - c) * kx * kx;
  }
  const Mat3 R1 = align * rr.transpose(), R2 = align * rr;
  const Vec3 t_new = R2 * T;
  const RawCamera* cams[2] = {&rig.left, &rig.right};
  const Mat3 Rk[2] = {R1, R2};

  // One focal length, the mean fy; each camera's principal point centres its
  // four undistorted corners, and both take the mean (zero disparity at
  // infinity).
  double f = (rig.left.K[4] + rig.right.K[4]) / 2;
  double cx = 0, cy = 0;
  for (int cam = 0; cam < 2; ++cam) {
    double sx = 0, sy = 0;
    for (int i = 0; i < 4; ++i) {
      double x, y;
      normalised(*cams[cam], (i % 2) * (W - 1.0), (i / 2) * (H - 1.0), kRectifyIterations, &x, &y);
      const Vec3 p = Rk[cam] * Vec3(x, y, 1);
      sx += f * p(0) / p(2);
      sy += f * p(1) / p(2);
    }
    cx += ((W - 1) / 2.0 - sx / 4) / 2;
    cy += ((H - 1) / 2.0 - sy / 4) / 2;
  }
  // alpha 0: scale f about the principal point until each camera's inner
  // rectangle (bounded by its undistorted border) covers the whole image.
  double scale = 0;
  for (int cam = 0; cam < 2; ++cam) {
    double ix0 = -HUGE_VAL, ix1 = HUGE_VAL, iy0 = -HUGE_VAL, iy1 = HUGE_VAL;
    for (int gy = 0; gy < kGrid; ++gy)
      for (int gx = 0; gx < kGrid; ++gx) {
        if (gx != 0 && gx != kGrid - 1 && gy != 0 && gy != kGrid - 1) continue;
        double x, y;
        normalised(*cams[cam], gx * static_cast<double>(W) / (kGrid - 1), gy * static_cast<double>(H) / (kGrid - 1),
                   kRectifyIterations, &x, &y);
        const Vec3 p = Rk[cam] * Vec3(x, y, 1);
        const double u = f * p(0) / p(2) + cx, v = f * p(1) / p(2) + cy;
        if (gx == 0) ix0 = std::fmax(ix0, u);
        if (gx == kGrid - 1) ix1 = std::fmin(ix1, u);
        if (gy == 0) iy0 = std::fmax(iy0, v);
        if (gy == kGrid - 1) iy1 = std::fmin(iy1, v);
      }
    if (!(ix0 < cx && cx < ix1 && iy0 < cy && cy < iy1))
      refuse(rig.path, "the rectified images have no valid area around the principal point (a distortion model "
                       "that folds over inside the image?)");
    scale = std::fmax(scale, std::fmax(std::fmax(cx / (cx - ix0), cy / (cy - iy0)),
                                       std::fmax((W - cx) / (ix1 - cx), (H - cy) / (iy1 - cy))));
  }
  f *= scale;
  Rectification out;
  out.R1 = arr9(R1);
  out.R2 = arr9(R2);
  out.P1 = {f, 0, cx, 0, 0, f, cy, 0, 0, 0, 1, 0};
  out.P2 = {f, 0, cx, t_new(0) * f, 0, f, cy, 0, 0, 0, 1, 0};
  out.width = W;
  out.height = H;
  out.from_file = false;
  return out;
}

Rectification rectify_rig(const StereoRig& rig) {
  if (!rig.has_rectification) return compute_rectification(rig);
  Rectification r;
  r.R1 = rig.R1;
  r.R2 = rig.R2;
  r.P1 = rig.P1;
  r.P2 = rig.P2;
  r.width = rig.left.width;
  r.height = rig.left.height;
  r.from_file = true;
  // What the matcher needs of a given rectification: one focal length, rows
  // aligned (one cy, no vertical offset), the right camera to the right.
  if (!(r.P1[0] > 0) || r.P1[0] != r.P2[0] || r.P1[5] != r.P2[5] || r.P1[0] != r.P1[5])
    refuse(rig.path, "P1 and P2 do not share one focal length: not a rectification for horizontal stereo");
  if (r.P1[6] != r.P2[6] || r.P2[7] != 0 || r.P1[7] != 0)
    refuse(rig.path, "P1 and P2 have different rows (cy or a vertical offset): not a horizontal rectification");
  if (!(r.P2[3] - r.P1[3] < 0))
    refuse(rig.path, "P2(0,3) = -f B is not negative: the right camera is not to the right (left and right swapped?)");
  return r;
}

StereoCalibration Rectification::calibration() const {
  StereoCalibration c;
  c.focal_px = P1[0];
  c.cx_px = P1[2];
  c.cy_px = P1[6];
  c.doffs_px = P2[2] - P1[2];
  c.baseline_m = -(P2[3] - P1[3]) / P2[0];
  c.width = width;
  c.height = height;
  return c;
}

RectifyProjector::RectifyProjector(const StereoRig& rig, const Rectification& rect, int camera)
    : cam_(camera == 0 ? rig.left : rig.right) {
  const std::array<double, 12>& P = camera == 0 ? rect.P1 : rect.P2;
  Mat3 Kp;
  Kp << P[0], P[1], P[2], P[4], P[5], P[6], P[8], P[9], P[10];
  const Mat3 back = (Kp * mat3(camera == 0 ? rect.R1 : rect.R2)).inverse();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m_[3 * i + j] = back(i, j);
}

void RectifyProjector::raw(double u, double v, double* x, double* y) const {
  const double X = m_[0] * u + m_[1] * v + m_[2];
  const double Y = m_[3] * u + m_[4] * v + m_[5];
  const double Z = m_[6] * u + m_[7] * v + m_[8];
  if (!(Z > 0)) {
    *x = *y = NAN;
    return;
  }
  double xd, yd;
  lens_distort(cam_, X / Z, Y / Z, &xd, &yd);
  const std::array<double, 9>& K = cam_.K;
  *x = K[0] * xd + K[1] * yd + K[2];
  *y = K[4] * yd + K[5];
}

void raw_position(const StereoRig& rig, const Rectification& rect, int camera, double u, double v, double* x,
                  double* y) {
  RectifyProjector(rig, rect, camera).raw(u, v, x, y);
}

void rectified_position(const StereoRig& rig, const Rectification& rect, int camera, double x, double y, double* u,
                        double* v) {
  const RawCamera& cam = camera == 0 ? rig.left : rig.right;
  double nx, ny;
  normalised(cam, x, y, 200, &nx, &ny);
  const Vec3 p = mat3(camera == 0 ? rect.R1 : rect.R2) * Vec3(nx, ny, 1);
  const std::array<double, 12>& P = camera == 0 ? rect.P1 : rect.P2;
  const double w = P[8] * p(0) + P[9] * p(1) + P[10] * p(2);
  *u = (P[0] * p(0) + P[1] * p(1) + P[2] * p(2)) / w;
  *v = (P[4] * p(0) + P[5] * p(1) + P[6] * p(2)) / w;
}

}  // namespace tristereo
