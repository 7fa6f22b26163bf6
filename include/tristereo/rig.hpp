// Raw cameras in: the calibration of an unrectified stereo rig, and its
// rectification.
//
// read_rig() reads the files users already have (docs/calibration.md, "Raw
// rigs"), recognising the format from the contents:
//   - an OpenCV stereoCalibrate result written by cv::FileStorage (YAML or
//     XML): M1 D1 M2 D2 R T, and R1 R2 P1 P2 when stereoRectify's outputs are
//     there too;
//   - a pair of ROS camera_info YAML files (camera_matrix, distortion_model,
//     distortion_coefficients, rectification_matrix, projection_matrix);
//   - a Kalibr camchain.yaml (cam0, cam1: intrinsics, distortion_model,
//     distortion_coeffs, resolution; cam1's T_cn_cnm1);
//   - a pair of EuRoC sensor.yaml files (intrinsics, distortion_coefficients,
//     resolution, T_BS: the camera's pose in the body frame).
// Every error names the file, the line (where there is one) and the key.
//
// rectify_rig() gives the rectification: the file's own R1 R2 P1 P2 when it
// has them, else computed in double precision (the construction of OpenCV's
// stereoRectify with CALIB_ZERO_DISPARITY and alpha 0: both cameras rotated
// to a common orientation with the baseline along x, one focal length, one
// principal point, scaled so that every rectified pixel sees the raw image).
#pragma once

#include <array>
#include <string>

#include "tristereo/calib.hpp"
#include "tristereo/export.hpp"

namespace tristereo {

// OpenCV's coefficient order throughout. ROS names in brackets.
enum class DistortionModel {
  kRadTan,       // k1 k2 p1 p2 [k3]  (plumb_bob; Kalibr/EuRoC radtan, radial-tangential)
  kRational,     // k1 k2 p1 p2 k3 k4 k5 k6  (rational_polynomial)
  kEquidistant,  // k1 k2 k3 k4, the fisheye model  (equidistant; Kalibr equidistant)
};

enum class RigFormat { kAuto, kOpenCv, kRosCameraInfo, kKalibr, kEuroc };

struct TRISTEREO_API RawCamera {
  // Row-major pinhole matrix [fx s cx; 0 fy cy; 0 0 1] of the raw image.
  std::array<double, 9> K{};
  DistortionModel model = DistortionModel::kRadTan;
  // kRadTan / kRational: k1 k2 p1 p2 k3 k4 k5 k6 (unused ones 0);
  // kEquidistant: k1 k2 k3 k4 in the first four.
  std::array<double, 8> dist{};
  int width = 0;  // raw image size
  int height = 0;
};

struct TRISTEREO_API StereoRig {
  RawCamera left, right;
  // Pose of the left camera in the right camera's frame, OpenCV's
  // convention: p_right = R p_left + T, T in metres (a stereo rig with the
  // right camera to the right has T ~ (-baseline, 0, 0)).
  std::array<double, 9> R{};
  std::array<double, 3> T{};
  // The rectification the file gives (stereoRectify's R1 R2 P1 P2, or ROS's
  // rectification and projection matrices), if any. P2(0,3) = -f B in the
  // same unit as T once read (metres).
  bool has_rectification = false;
  std::array<double, 9> R1{}, R2{};
  std::array<double, 12> P1{}, P2{};
  RigFormat format = RigFormat::kAuto;
  std::string path;        // the file it came from (the left one of a pair)
  std::string right_path;  // the right one of a pair ("" for a one-file format)
};

// Reads a rig. `right_path` is the right camera's file for the two-file
// formats (ROS camera_info, EuRoC sensor.yaml) and must be "" for the others.
// unit_m: the length of one unit of an OpenCV or ROS file's translations in
// metres (OpenCV stores none; 1 when the target was measured in metres);
// Kalibr and EuRoC state metres. Throws Error (kIoError, kCorruptFile,
// kUnsupportedFormat, kInvalidArgument) naming the file, line and key: missing
// keys, non-numbers, wrong matrix shapes, an unknown distortion model, focal
// lengths or principal points outside check_camera_bounds(), a rotation that
// is not one, a baseline outside [kMinBaselineM, kMaxBaselineM], cameras of
// different image sizes.
TRISTEREO_API StereoRig read_rig(const std::string& path, const std::string& right_path = "",
                                 double unit_m = 1.0);

// The format read_rig would read, from the contents (kAuto: none of them).
TRISTEREO_API RigFormat detect_rig_format(const std::string& path);
TRISTEREO_API bool rig_format_needs_pair(RigFormat format);

struct TRISTEREO_API Rectification {
  // Rotations from each raw camera's frame to its rectified frame, and the
  // rectified 3x4 projections: P1 = [f 0 cx 0; 0 f cy 0; 0 0 1 0],
  // P2 = [f 0 cx2 -f B; 0 f cy 0; 0 0 1 0] (B in metres).
  std::array<double, 9> R1{}, R2{};
  std::array<double, 12> P1{}, P2{};
  int width = 0;  // rectified image size (the raw size)
  int height = 0;
  bool from_file = false;  // the file's own, not computed

  // The geometry of the rectified pair for depth and points
  // (StereoCalibration::camera(): Z = f B / (d + doffs)).
  StereoCalibration calibration() const;
};

// The file's rectification when it has one, else computed (see the top of
// this header). Throws Error(kInvalidArgument) when the rig's cameras are
// not side by side (the baseline's largest component after the common
// rotation is not x) or the result is degenerate.
TRISTEREO_API Rectification rectify_rig(const StereoRig& rig);
// Always computes it, even when the file has one (for comparisons).
TRISTEREO_API Rectification compute_rectification(const StereoRig& rig);

// Where rectified pixel (u, v) of camera `camera` (0 left, 1 right) comes
// from in its raw image, in double precision (x right, y down, (0, 0) the
// centre of the top-left pixel). Non-finite when the ray points behind the
// camera or outside the distortion model's domain. This is the one
// definition of the map: the fixed-point maps (rectify.hpp) and the float
// reference round exactly these values.
TRISTEREO_API void raw_position(const StereoRig& rig, const Rectification& rect, int camera, double u, double v,
                                double* x, double* y);

// The rectified position of raw pixel (x, y) of camera `camera` (the inverse
// of raw_position, by fixed-point iteration of the distortion): for corners
// and feature points.
TRISTEREO_API void rectified_position(const StereoRig& rig, const Rectification& rect, int camera, double x,
                                      double y, double* u, double* v);

TRISTEREO_API const char* to_string(RigFormat format);
TRISTEREO_API const char* to_string(DistortionModel model);

}  // namespace tristereo
