// read_calibration(): recognise the format, hand the lines to its reader.
#include <cmath>
#include <cstdio>

#include "src/calib/calib_text.hpp"

namespace tristereo {

using calib_detail::Line;

namespace {

CalibFormat detect(const std::string& path, const std::vector<Line>& lines) {
  for (const Line& l : lines) {
    const std::string t = calib_detail::trim(l.text);
    if (t.rfind("%YAML", 0) == 0 || t.find("<opencv_storage>") != std::string::npos)
      return CalibFormat::kOpenCv;
    if (t.rfind("cam0", 0) == 0 && t.find('=') != std::string::npos) return CalibFormat::kMiddlebury;
    if (t.rfind("P0:", 0) == 0 || t.rfind("P2:", 0) == 0 || t.rfind("P_rect_02:", 0) == 0)
      return CalibFormat::kKitti;
  }
  throw Error(ErrorCode::kUnsupportedFormat,
              "calibration file '" + path +
                  "': not a Middlebury calib.txt (cam0=...), a KITTI calibration (P2: ...) "
                  "or an OpenCV YAML/XML file (%YAML / <opencv_storage>)");
}

}  // namespace

CameraParams StereoCalibration::camera() const {
  CameraParams c{};
  c.focal_px = focal_px;
  c.baseline = baseline_m;
  c.cx = cx_px;
  c.cy = cy_px;
  c.doffs = doffs_px;
  return c;
}

StereoCalibration read_calibration(const std::string& path, CalibFormat format, double opencv_unit_m) {
  if (!(opencv_unit_m > 0) || !std::isfinite(opencv_unit_m))
    throw Error(ErrorCode::kInvalidArgument,
                "calibration unit must be > 0 metres, got " + std::to_string(opencv_unit_m));
  const std::vector<Line> lines = calib_detail::read_lines(path);
  if (format == CalibFormat::kAuto) format = detect(path, lines);
  switch (format) {
    case CalibFormat::kMiddlebury: return calib_detail::read_middlebury(path, lines);
    case CalibFormat::kKitti: return calib_detail::read_kitti(path, lines);
    case CalibFormat::kOpenCv: return calib_detail::read_opencv_file(path, lines, opencv_unit_m);
    case CalibFormat::kAuto: break;
  }
  throw Error(ErrorCode::kInvalidArgument, "unknown calibration format");
}

CameraBoundsCheck check_camera_bounds(const CameraParams& c, int width, int height) {
  const double w = width > 0 ? width : kMaxReadSide, h = height > 0 ? height : kMaxReadSide;
  CameraBoundsCheck out;
  // %g: a typo such as 1e300 must not print as 300 digits.
  auto outside = [&](CameraField field, const char* what, double v, double lo, double hi, const char* unit) {
    if (out || (v >= lo && v <= hi)) return;  // NaN fails both comparisons
    char text[160];
    std::snprintf(text, sizeof text, "%s %.6g%s is outside [%.6g, %.6g]%s", what, v, unit, lo, hi, unit);
    out.field = field;
    out.message = text;
  };
  outside(CameraField::kFocal, "focal length", c.focal_px, kMinFocalPx, kMaxFocalPx, " px");
  outside(CameraField::kBaseline, "baseline", c.baseline, kMinBaselineM, kMaxBaselineM, " m");
  outside(CameraField::kPrincipalPoint, "principal point cx", c.cx, -w, 2 * w, " px");
  outside(CameraField::kPrincipalPoint, "principal point cy", c.cy, -h, 2 * h, " px");
  outside(CameraField::kDoffs, "doffs", c.doffs, -3 * w, 3 * w, " px");
  if (out && (out.field == CameraField::kPrincipalPoint || out.field == CameraField::kDoffs)) {
    char size[96];
    std::snprintf(size, sizeof size, " (for %s %.0fx%.0f image)", width > 0 ? "a" : "the largest readable,", w, h);
    out.message += size;
  }
  return out;
}

void check_calibration_size(const StereoCalibration& calib, int width, int height) {
  if (calib.width == 0 && calib.height == 0) return;
  if (calib.width != width || calib.height != height)
    throw Error(ErrorCode::kSizeMismatch,
                "calibration file '" + calib.path + "' is for " + std::to_string(calib.width) + "x" +
                    std::to_string(calib.height) + " images, the input is " + std::to_string(width) +
                    "x" + std::to_string(height) + " (a calibration of another resolution)");
}

const char* to_string(CalibFormat format) {
  switch (format) {
    case CalibFormat::kAuto: return "auto";
    case CalibFormat::kMiddlebury: return "middlebury";
    case CalibFormat::kKitti: return "kitti";
    case CalibFormat::kOpenCv: return "opencv";
  }
  return "?";
}

CalibFormat parse_calib_format(const std::string& name) {
  for (CalibFormat f : {CalibFormat::kAuto, CalibFormat::kMiddlebury, CalibFormat::kKitti, CalibFormat::kOpenCv})
    if (name == to_string(f)) return f;
  throw Error(ErrorCode::kInvalidArgument,
              "calibration format '" + name + "' (expected auto, middlebury, kitti or opencv)");
}

}  // namespace tristereo
