// A Kalibr camchain.yaml (kalibr_calibrate_cameras' output): cam0 and cam1,
// each with camera_model (pinhole), intrinsics [fu, fv, pu, pv],
// distortion_model (radtan or equidistant), distortion_coeffs and resolution
// [width, height]; cam1's T_cn_cnm1 (4x4, rows as sequences) takes points
// from cam0's frame to cam1's: p_cam1 = T_cn_cnm1 p_cam0, which is OpenCV's
// [R | T] as it stands. Metres.
#include "src/calib/rig_readers.hpp"

namespace tristereo::calib_detail {

namespace {

void read_camera(const std::string& path, const YamlNode& cam, const std::string& name, RawCamera* out,
                 RigOrigins* at, int c) {
  const YamlNode& model = yaml_get(cam, "camera_model", path, name + "/camera_model");
  const std::string m = yaml_string(model, path, name + "/camera_model");
  if (m != "pinhole")
    fail(ErrorCode::kUnsupportedFormat, path, model.line, name + "/camera_model",
         "camera model '" + m + "' is not supported (pinhole)");
  const YamlNode& in = yaml_get(cam, "intrinsics", path, name + "/intrinsics");
  const std::vector<double> k = yaml_numbers(in, 4, path, name + "/intrinsics");
  out->K = pinhole(k[0], k[1], k[2], k[3]);
  at->k[c] = {path, in.line, name + "/intrinsics"};
  const YamlNode& dm = yaml_get(cam, "distortion_model", path, name + "/distortion_model");
  const DistortionModel model_kind = distortion_model_named(yaml_string(dm, path, name + "/distortion_model"),
                                                            {path, dm.line, name + "/distortion_model"});
  const YamlNode& dc = yaml_get(cam, "distortion_coeffs", path, name + "/distortion_coeffs");
  at->dist[c] = {path, dc.line, name + "/distortion_coeffs"};
  set_distortion(*out, model_kind, yaml_numbers(dc, path, name + "/distortion_coeffs"), at->dist[c]);
  const YamlNode& res = yaml_get(cam, "resolution", path, name + "/resolution");
  const std::vector<double> s = yaml_numbers(res, 2, path, name + "/resolution");
  at->size[c] = {path, res.line, name + "/resolution"};
  set_size(*out, s[0], s[1], at->size[c]);
}

}  // namespace

StereoRig read_rig_kalibr(const std::string& path, const YamlNode& root) {
  StereoRig rig;
  RigOrigins at;
  const YamlNode& cam0 = yaml_get(root, "cam0", path, "cam0");
  const YamlNode& cam1 = yaml_get(root, "cam1", path, "cam1");
  read_camera(path, cam0, "cam0", &rig.left, &at, 0);
  read_camera(path, cam1, "cam1", &rig.right, &at, 1);
  const YamlNode& t = yaml_get(cam1, "T_cn_cnm1", path, "cam1/T_cn_cnm1");
  const std::vector<double> m = yaml_numbers(t, 16, path, "cam1/T_cn_cnm1");
  if (m[12] != 0 || m[13] != 0 || m[14] != 0 || m[15] != 1)
    fail(ErrorCode::kCorruptFile, path, t.line, "cam1/T_cn_cnm1", "the last row must be [0, 0, 0, 1]");
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) rig.R[static_cast<std::size_t>(3 * i + j)] = m[static_cast<std::size_t>(4 * i + j)];
    rig.T[static_cast<std::size_t>(i)] = m[static_cast<std::size_t>(4 * i + 3)];
  }
  at.rotation = at.translation = {path, t.line, "cam1/T_cn_cnm1"};
  validate_rig(rig, at);
  return rig;
}

}  // namespace tristereo::calib_detail
