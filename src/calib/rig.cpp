// read_rig(): recognise the format of a raw rig's calibration, hand it to its
// reader, and hold every format to the same bounds.
#include <cmath>
#include <cstdio>

#include "src/calib/rig_readers.hpp"
#include "tristereo/io.hpp"

namespace tristereo {

using calib_detail::fail;
using calib_detail::Line;
using calib_detail::Origin;
using calib_detail::YamlNode;

namespace calib_detail {

DistortionModel distortion_model_named(const std::string& name, const Origin& at) {
  if (name == "plumb_bob" || name == "radtan" || name == "radial-tangential") return DistortionModel::kRadTan;
  if (name == "rational_polynomial") return DistortionModel::kRational;
  if (name == "equidistant" || name == "fisheye") return DistortionModel::kEquidistant;
  fail(ErrorCode::kUnsupportedFormat, at.path, at.line, at.key,
       "distortion model '" + name +
           "' is not supported (plumb_bob/radtan/radial-tangential, rational_polynomial, equidistant)");
}

void set_distortion(RawCamera& cam, DistortionModel model, const std::vector<double>& c, const Origin& at) {
  const std::size_t n = c.size();
  bool ok = false;
  switch (model) {
    case DistortionModel::kRadTan: ok = n == 4 || n == 5; break;
    case DistortionModel::kRational: ok = n == 8 || n == 12 || n == 14; break;
    case DistortionModel::kEquidistant: ok = n == 4; break;
  }
  if (!ok)
    fail(ErrorCode::kCorruptFile, at.path, at.line, at.key,
         std::string("expected ") +
             (model == DistortionModel::kRadTan       ? "4 or 5 coefficients (k1 k2 p1 p2 [k3])"
              : model == DistortionModel::kRational   ? "8 coefficients (k1 k2 p1 p2 k3 k4 k5 k6)"
                                                      : "4 coefficients (k1 k2 k3 k4)") +
             " for " + to_string(model) + ", got " + std::to_string(n));
  // OpenCV's 12 and 14 coefficient vectors add thin-prism and tilt terms,
  // which this library does not model: only zeros there are accepted.
  for (std::size_t i = 8; i < n; ++i)
    if (c[i] != 0)
      fail(ErrorCode::kUnsupportedFormat, at.path, at.line, at.key,
           "coefficient " + std::to_string(i + 1) +
               " (thin-prism s1..s4 or tilt tx, ty) is not 0: that model is not supported");
  cam.model = model;
  cam.dist = {};
  for (std::size_t i = 0; i < n && i < 8; ++i) cam.dist[i] = c[i];
}

std::array<double, 9> pinhole(double fx, double fy, double cx, double cy) {
  return {fx, 0, cx, 0, fy, cy, 0, 0, 1};
}

void set_size(RawCamera& cam, double w, double h, const Origin& at) {
  for (double v : {w, h})
    if (!(v == std::floor(v)) || v < 2 || v > kMaxReadSide)
      fail(ErrorCode::kCorruptFile, at.path, at.line, at.key,
           "image size must be whole numbers in 2.." + std::to_string(kMaxReadSide));
  cam.width = static_cast<int>(w);
  cam.height = static_cast<int>(h);
}

void validate_rig(const StereoRig& rig, const RigOrigins& at) {
  const RawCamera* cams[2] = {&rig.left, &rig.right};
  for (int c = 0; c < 2; ++c) {
    const RawCamera& cam = *cams[c];
    const Origin& k = at.k[c];
    const std::array<double, 9>& K = cam.K;
    if (K[3] != 0 || K[6] != 0 || K[7] != 0 || K[8] != 1)
      fail(ErrorCode::kInvalidArgument, k.path, k.line, k.key, "the camera matrix's last rows must be [0 fy cy; 0 0 1]");
    // fx, fy and the principal point: the rectified rig's bounds hold for the
    // raw cameras too (a focal length in the wrong unit is as wrong here).
    for (double f : {K[0], K[4]}) {
      CameraParams p{f, kMinBaselineM, K[2], K[5], 0};
      const CameraBoundsCheck check = check_camera_bounds(p, cam.width, cam.height);
      if (check) fail(ErrorCode::kInvalidArgument, k.path, k.line, k.key, check.message);
    }
    if (!(std::fabs(K[1]) <= K[0]))
      fail(ErrorCode::kInvalidArgument, k.path, k.line, k.key, "the skew is larger than the focal length");
    for (double d : cam.dist)
      if (!(std::fabs(d) <= 1e4))
        fail(ErrorCode::kInvalidArgument, at.dist[c].path, at.dist[c].line, at.dist[c].key,
             "a distortion coefficient beyond +-1e4 is not a lens");
  }
  if (rig.left.width != rig.right.width || rig.left.height != rig.right.height)
    fail(ErrorCode::kSizeMismatch, at.size[1].path, at.size[1].line, at.size[1].key,
         "the right camera's images are " + std::to_string(rig.right.width) + "x" + std::to_string(rig.right.height) +
             ", the left camera's " + std::to_string(rig.left.width) + "x" + std::to_string(rig.left.height) +
             " (both must have one size)");
  const std::array<double, 9>& R = rig.R;
  double worst = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double dot = 0;
      for (int m = 0; m < 3; ++m) dot += R[3 * m + i] * R[3 * m + j];
      worst = std::fmax(worst, std::fabs(dot - (i == j ? 1.0 : 0.0)));
    }
  const double det = R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) +
                     R[2] * (R[3] * R[7] - R[4] * R[6]);
  if (!(worst <= 1e-6) || !(det > 0)) {
    char text[160];
    std::snprintf(text, sizeof text, "is not a rotation (R^T R differs from I by %.3g, det %.6g)", worst, det);
    fail(ErrorCode::kInvalidArgument, at.rotation.path, at.rotation.line, at.rotation.key, text);
  }
  const double b = std::sqrt(rig.T[0] * rig.T[0] + rig.T[1] * rig.T[1] + rig.T[2] * rig.T[2]);
  if (!(b >= kMinBaselineM && b <= kMaxBaselineM)) {
    char text[160];
    std::snprintf(text, sizeof text, "baseline |T| = %.6g m is outside [%.6g, %.6g] m", b, kMinBaselineM, kMaxBaselineM);
    fail(ErrorCode::kInvalidArgument, at.translation.path, at.translation.line, at.translation.key, text);
  }
}

}  // namespace calib_detail

namespace {

bool is_xml(const std::vector<Line>& lines) {
  for (const Line& l : lines)
    if (l.text.find("<opencv_storage>") != std::string::npos) return true;
  return false;
}

RigFormat format_of(const std::string& path, const std::vector<Line>& lines, YamlNode* root) {
  if (is_xml(lines)) return RigFormat::kOpenCv;
  *root = calib_detail::parse_yaml_tree(path, lines);
  if (root->kind != YamlNode::kMap) return RigFormat::kAuto;
  if (root->find("M1") && root->find("M2")) return RigFormat::kOpenCv;
  if (root->find("camera_matrix")) return RigFormat::kRosCameraInfo;
  if (root->find("cam0") && root->find("cam1")) return RigFormat::kKalibr;
  if (root->find("T_BS") && root->find("intrinsics")) return RigFormat::kEuroc;
  return RigFormat::kAuto;
}

[[noreturn]] void unknown(const std::string& path) {
  throw Error(ErrorCode::kUnsupportedFormat,
              "calibration file '" + path +
                  "': not a raw stereo rig (an OpenCV stereoCalibrate file with M1 D1 M2 D2 R T, a ROS "
                  "camera_info YAML with camera_matrix, a Kalibr camchain with cam0 and cam1, or an EuRoC "
                  "sensor.yaml with T_BS and intrinsics)");
}

}  // namespace

RigFormat detect_rig_format(const std::string& path) {
  const std::vector<Line> lines = calib_detail::read_lines(path);
  YamlNode root;
  return format_of(path, lines, &root);
}

bool rig_format_needs_pair(RigFormat format) {
  return format == RigFormat::kRosCameraInfo || format == RigFormat::kEuroc;
}

StereoRig read_rig(const std::string& path, const std::string& right_path, double unit_m) {
  if (!(unit_m > 0) || !std::isfinite(unit_m))
    throw Error(ErrorCode::kInvalidArgument, "calibration unit must be > 0 metres, got " + std::to_string(unit_m));
  const std::vector<Line> lines = calib_detail::read_lines(path);
  YamlNode root;
  const RigFormat format = format_of(path, lines, &root);
  if (format == RigFormat::kAuto) unknown(path);
  if (rig_format_needs_pair(format) != !right_path.empty()) {
    if (right_path.empty())
      throw Error(ErrorCode::kInvalidArgument,
                  "calibration file '" + path + "' is a " + to_string(format) +
                      " file of one camera: the right camera's file is needed too");
    throw Error(ErrorCode::kInvalidArgument, "calibration file '" + path + "' is a " + to_string(format) +
                                                 " file of the whole rig: a second file ('" + right_path +
                                                 "') has no place beside it");
  }
  StereoRig rig;
  if (format == RigFormat::kOpenCv) {
    rig = calib_detail::read_rig_opencv(path, lines, unit_m);
  } else if (format == RigFormat::kKalibr) {
    rig = calib_detail::read_rig_kalibr(path, root);
  } else {
    const std::vector<Line> right_lines = calib_detail::read_lines(right_path);
    YamlNode right_root;
    const RigFormat right_format = format_of(right_path, right_lines, &right_root);
    if (right_format != format)
      throw Error(ErrorCode::kUnsupportedFormat, "calibration file '" + right_path + "' is not a " +
                                                     to_string(format) + " file like '" + path + "'");
    rig = format == RigFormat::kRosCameraInfo
              ? calib_detail::read_rig_ros(path, root, right_path, right_root, unit_m)
              : calib_detail::read_rig_euroc(path, root, right_path, right_root);
    rig.right_path = right_path;
  }
  rig.format = format;
  rig.path = path;
  return rig;
}

const char* to_string(RigFormat format) {
  switch (format) {
    case RigFormat::kAuto: return "auto";
    case RigFormat::kOpenCv: return "OpenCV stereo calibration";
    case RigFormat::kRosCameraInfo: return "ROS camera_info";
    case RigFormat::kKalibr: return "Kalibr camchain";
    case RigFormat::kEuroc: return "EuRoC sensor.yaml";
  }
  return "?";
}

const char* to_string(DistortionModel model) {
  switch (model) {
    case DistortionModel::kRadTan: return "plumb_bob";
    case DistortionModel::kRational: return "rational_polynomial";
    case DistortionModel::kEquidistant: return "equidistant";
  }
  return "?";
}

}  // namespace tristereo
