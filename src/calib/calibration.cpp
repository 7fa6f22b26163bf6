// read_calibration(): recognise the format, hand the lines to its reader.
#include <cmath>

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
