// Stereo calibration in, metric depth out.
//
// read_calibration() reads the files users already have and turns them into
// the pinhole parameters of the rectified left view:
//   - Middlebury calib.txt (cam0=[f 0 cx; 0 f cy; 0 0 1], cam1, doffs,
//     baseline in mm, width, height);
//   - a KITTI calibration file ("P2: 12 numbers" and "P3: ...", or P0/P1: the
//     rectified 3x4 projection matrices; baseline from their 4th column);
//   - an OpenCV stereo calibration written by cv::FileStorage (YAML or XML)
//     holding the output of stereoRectify: P1 and P2, or Q.
// Every error names the file, the line (where there is one) and the key.
#pragma once

#include <string>

#include "tristereo/export.hpp"
#include "tristereo/io.hpp"

namespace tristereo {

enum class CalibFormat { kAuto, kMiddlebury, kKitti, kOpenCv };

struct TRISTEREO_API StereoCalibration {
  double focal_px = 0;    // focal length of the rectified left view, pixels
  double baseline_m = 0;  // distance between the optical centres, metres
  double cx_px = 0;       // principal point of the left view, pixels
  double cy_px = 0;
  double doffs_px = 0;    // cx of the right view minus cx of the left view, pixels
  int width = 0;          // image size the file states (0 = it states none)
  int height = 0;
  CalibFormat format = CalibFormat::kAuto;  // the format that was read
  std::string path;                          // the file it came from

  // Z = focal_px * baseline_m / (d + doffs_px), X = (x - cx_px) Z / focal_px,
  // Y = (y - cy_px) Z / focal_px (metres, camera frame, y down).
  CameraParams camera() const;
};

// Throws Error (kIoError, kCorruptFile, kUnsupportedFormat, kInvalidArgument)
// naming the file, line and key on missing keys, non-numeric values, and
// values outside the bounds below (check_camera_bounds, with the size the file
// states, if any). kAuto recognises the format from the
// contents ("cam0=" lines, "P2:"/"P0:" lines, "%YAML" or "<opencv_storage>").
// opencv_unit_m: the length of one unit of an OpenCV file's translations in
// metres (OpenCV stores no unit: 1 when the target was measured in metres,
// 0.001 in millimetres); Middlebury (mm) and KITTI (m) state theirs.
TRISTEREO_API StereoCalibration read_calibration(const std::string& path,
                                                 CalibFormat format = CalibFormat::kAuto,
                                                 double opencv_unit_m = 1.0);

// The bounds a real rectified rig stays within (docs/calibration.md,
// "Bounds"), the same for every calibration format (read_calibration checks
// them) and for the command line's --camera: a value outside them is a typo or
// a wrong unit, and would make every depth 0, infinite or meaningless.
constexpr double kMinFocalPx = 1;       // 1 px is already a 179.6-degree view of a 640-px image
constexpr double kMaxFocalPx = 1e6;     // a 1000 mm lens on 1 um pixels is 1e6 px
constexpr double kMinBaselineM = 1e-4;  // 0.1 mm (stereo endoscopes: a few mm)
constexpr double kMaxBaselineM = 1e3;   // 1 km (aerial stereo)
// The principal point lies within [-W, 2W] x [-H, 2H] and |doffs| <= 3 W,
// for the image size W x H (the input's, or the file's; kMaxReadSide when
// neither is known): rectification moves it, but not that far.

enum class CameraField { kNone, kFocal, kBaseline, kPrincipalPoint, kDoffs };
struct CameraBoundsCheck {
  CameraField field = CameraField::kNone;  // the first value outside its bounds
  std::string message;  // e.g. "focal length 1e+300 px is outside [1, 1e+06] px"
  explicit operator bool() const { return field != CameraField::kNone; }
};
// camera.baseline in metres; width/height 0 = unknown. Numbers in the message
// have at most 6 significant digits.
TRISTEREO_API CameraBoundsCheck check_camera_bounds(const CameraParams& camera, int width, int height);

// Throws Error(kSizeMismatch) when the calibration states an image size and
// width x height is not it.
TRISTEREO_API void check_calibration_size(const StereoCalibration& calib, int width, int height);

TRISTEREO_API const char* to_string(CalibFormat format);
// "auto" | "middlebury" | "kitti" | "opencv"; throws kInvalidArgument otherwise.
TRISTEREO_API CalibFormat parse_calib_format(const std::string& name);

}  // namespace tristereo
