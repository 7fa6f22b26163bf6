// A pair of EuRoC MAV sensor.yaml files (cam0/sensor.yaml, cam1/sensor.yaml):
// intrinsics [fu, fv, cu, cv], distortion_model (radial-tangential or
// equidistant), distortion_coefficients, resolution [width, height], and T_BS
// (4x4 as rows, cols, data): the camera's pose in the body (IMU) frame, which
// takes the camera's points to the body's, p_B = T_BS p_S.
//
// The stereo pose follows: p_cam1 = inv(T_BS1) T_BS0 p_cam0, so
// R = R_BS1^T R_BS0 and T = R_BS1^T (t_BS0 - t_BS1), OpenCV's convention.
// Checked on EuRoC V1_01_easy (tests/rig_test.cpp): |T| = 0.110 m along -x
// (the right camera to the right); the other reading of T_BS would put the
// baseline along y, which the images contradict.
#include "src/calib/rig_readers.hpp"

namespace tristereo::calib_detail {

namespace {

struct One {
  RawCamera cam;
  std::vector<double> T_BS;
  Origin k, dist, size, pose;
};

One read_one(const std::string& path, const YamlNode& root) {
  One o;
  const YamlNode& in = yaml_get(root, "intrinsics", path, "intrinsics");
  const std::vector<double> k = yaml_numbers(in, 4, path, "intrinsics");
  o.cam.K = pinhole(k[0], k[1], k[2], k[3]);
  o.k = {path, in.line, "intrinsics"};
  if (const YamlNode* cm = root.find("camera_model")) {
    const std::string m = yaml_string(*cm, path, "camera_model");
    if (m != "pinhole")
      fail(ErrorCode::kUnsupportedFormat, path, cm->line, "camera_model",
           "camera model '" + m + "' is not supported (pinhole)");
  }
  const YamlNode& dm = yaml_get(root, "distortion_model", path, "distortion_model");
  const DistortionModel model =
      distortion_model_named(yaml_string(dm, path, "distortion_model"), {path, dm.line, "distortion_model"});
  const YamlNode& dc = yaml_get(root, "distortion_coefficients", path, "distortion_coefficients");
  o.dist = {path, dc.line, "distortion_coefficients"};
  set_distortion(o.cam, model, yaml_numbers(dc, path, "distortion_coefficients"), o.dist);
  const YamlNode& res = yaml_get(root, "resolution", path, "resolution");
  const std::vector<double> s = yaml_numbers(res, 2, path, "resolution");
  o.size = {path, res.line, "resolution"};
  set_size(o.cam, s[0], s[1], o.size);
  const YamlNode& t = yaml_get(root, "T_BS", path, "T_BS");
  o.pose = {path, t.line, "T_BS"};
  const YamlNode& data = t.kind == YamlNode::kMap ? yaml_get(t, "data", path, "T_BS/data") : t;
  if (t.kind == YamlNode::kMap) {
    const double rows = yaml_numbers(yaml_get(t, "rows", path, "T_BS/rows"), 1, path, "T_BS/rows")[0];
    const double cols = yaml_numbers(yaml_get(t, "cols", path, "T_BS/cols"), 1, path, "T_BS/cols")[0];
    if (rows != 4 || cols != 4) fail(ErrorCode::kCorruptFile, path, t.line, "T_BS", "expected 4x4");
  }
  o.T_BS = yaml_numbers(data, 16, path, "T_BS/data");
  const std::vector<double>& m = o.T_BS;
  if (m[12] != 0 || m[13] != 0 || m[14] != 0 || m[15] != 1)
    fail(ErrorCode::kCorruptFile, path, t.line, "T_BS", "the last row must be [0, 0, 0, 1]");
  return o;
}

}  // namespace

StereoRig read_rig_euroc(const std::string& left, const YamlNode& l, const std::string& right, const YamlNode& r) {
  const One a = read_one(left, l), b = read_one(right, r);
  StereoRig rig;
  rig.left = a.cam;
  rig.right = b.cam;
  auto rot = [](const std::vector<double>& m, int i, int j) { return m[static_cast<std::size_t>(4 * i + j)]; };
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double s = 0;
      for (int k = 0; k < 3; ++k) s += rot(b.T_BS, k, i) * rot(a.T_BS, k, j);
      rig.R[static_cast<std::size_t>(3 * i + j)] = s;
    }
    double s = 0;
    for (int k = 0; k < 3; ++k) s += rot(b.T_BS, k, i) * (rot(a.T_BS, k, 3) - rot(b.T_BS, k, 3));
    rig.T[static_cast<std::size_t>(i)] = s;
  }
  RigOrigins at = camera_origins(a, b);
  // A rotation that is not one comes from either T_BS; name the right one's.
  at.rotation = at.translation = b.pose;
  validate_rig(rig, at);
  return rig;
}

}  // namespace tristereo::calib_detail
