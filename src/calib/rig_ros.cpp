// A pair of ROS sensor_msgs/CameraInfo YAML files (camera_calibration's
// output, camera_info_manager's format): image_width, image_height,
// camera_matrix, distortion_model, distortion_coefficients,
// rectification_matrix, projection_matrix; each matrix a mapping of rows,
// cols and data.
//
// The pair always carries a rectification: R_k rotates camera k to the
// rectified frame, and in that frame the right camera sits at
// t = (-P2(0,3) / f, -P2(1,3) / f, 0) from the left one (ROS's Tx = -f B), so
// the raw pose is R = R2^T R1, T = R2^T (P2(0,3) / f, P2(1,3) / f, 0).
#include "src/calib/rig_readers.hpp"

namespace tristereo::calib_detail {

namespace {

std::vector<double> ros_matrix(const YamlNode& root, const std::string& key, int rows, int cols,
                               const std::string& path) {
  const YamlNode& m = yaml_get(root, key, path, key);
  if (m.kind != YamlNode::kMap) fail(ErrorCode::kCorruptFile, path, m.line, key, "expected rows, cols and data");
  const std::vector<double> r = yaml_numbers(yaml_get(m, "rows", path, key + "/rows"), 1, path, key + "/rows");
  const std::vector<double> c = yaml_numbers(yaml_get(m, "cols", path, key + "/cols"), 1, path, key + "/cols");
  if (cols > 0 && (r[0] != rows || c[0] != cols))
    fail(ErrorCode::kCorruptFile, path, m.line, key,
         "expected " + std::to_string(rows) + "x" + std::to_string(cols) + ", the file says " +
             std::to_string(static_cast<long long>(r[0])) + "x" + std::to_string(static_cast<long long>(c[0])));
  if (cols == 0 && !(r[0] == 1 || c[0] == 1))
    fail(ErrorCode::kCorruptFile, path, m.line, key, "expected a vector (rows or cols 1)");
  const YamlNode& data = yaml_get(m, "data", path, key + "/data");
  const std::vector<double> v = yaml_numbers(data, path, key + "/data");
  if (!(r[0] >= 0 && c[0] >= 0 && r[0] * c[0] == static_cast<double>(v.size())))
    fail(ErrorCode::kCorruptFile, path, data.line, key + "/data",
         "expected rows x cols numbers, got " + std::to_string(v.size()));
  return v;
}

struct One {
  RawCamera cam;
  std::vector<double> R, P;
  Origin k, dist, size, r, p;
};

One read_one(const std::string& path, const YamlNode& root) {
  One o;
  o.k = {path, yaml_get(root, "camera_matrix", path, "camera_matrix").line, "camera_matrix"};
  const std::vector<double> K = ros_matrix(root, "camera_matrix", 3, 3, path);
  for (std::size_t i = 0; i < 9; ++i) o.cam.K[i] = K[i];
  const YamlNode& model = yaml_get(root, "distortion_model", path, "distortion_model");
  const DistortionModel dm =
      distortion_model_named(yaml_string(model, path, "distortion_model"), {path, model.line, "distortion_model"});
  o.dist = {path, yaml_get(root, "distortion_coefficients", path, "distortion_coefficients").line,
            "distortion_coefficients"};
  set_distortion(o.cam, dm, ros_matrix(root, "distortion_coefficients", 1, 0, path), o.dist);
  const YamlNode& w = yaml_get(root, "image_width", path, "image_width");
  const YamlNode& h = yaml_get(root, "image_height", path, "image_height");
  o.size = {path, w.line, "image_width"};
  set_size(o.cam, yaml_numbers(w, 1, path, "image_width")[0], yaml_numbers(h, 1, path, "image_height")[0], o.size);
  o.R = ros_matrix(root, "rectification_matrix", 3, 3, path);
  o.P = ros_matrix(root, "projection_matrix", 3, 4, path);
  o.r = {path, yaml_get(root, "rectification_matrix", path, "").line, "rectification_matrix"};
  o.p = {path, yaml_get(root, "projection_matrix", path, "").line, "projection_matrix"};
  if (!(o.P[0] > 0))
    fail(ErrorCode::kInvalidArgument, path, o.p.line, o.p.key,
         "P(0,0) is not a focal length > 0 (an uncalibrated camera_info has zeros)");
  return o;
}

}  // namespace

StereoRig read_rig_ros(const std::string& left, const YamlNode& l, const std::string& right, const YamlNode& r,
                       double unit_m) {
  const One a = read_one(left, l), b = read_one(right, r);
  StereoRig rig;
  rig.left = a.cam;
  rig.right = b.cam;
  for (std::size_t i = 0; i < 9; ++i) {
    rig.R1[i] = a.R[i];
    rig.R2[i] = b.R[i];
  }
  for (std::size_t i = 0; i < 12; ++i) {
    rig.P1[i] = a.P[i];
    rig.P2[i] = b.P[i];
  }
  for (std::size_t i : {3u, 7u, 11u}) {
    rig.P1[i] *= unit_m;
    rig.P2[i] *= unit_m;
  }
  rig.has_rectification = true;
  // The rectified frames differ by t (P2's 4th column over f, less P1's);
  // back in the raw right frame that is R2^T t, and the rotation R2^T R1.
  const double f = rig.P2[0];
  const double t[3] = {(rig.P2[3] - rig.P1[3]) / f, (rig.P2[7] - rig.P1[7]) / f, 0};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double s = 0;
      for (int m = 0; m < 3; ++m) s += rig.R2[3 * m + i] * rig.R1[3 * m + j];
      rig.R[3 * i + j] = s;
    }
    double s = 0;
    for (int m = 0; m < 3; ++m) s += rig.R2[3 * m + i] * t[m];
    rig.T[i] = s;
  }
  RigOrigins at = camera_origins(a, b);
  at.rotation = b.r;
  at.translation = b.p;
  validate_rig(rig, at);
  return rig;
}

}  // namespace tristereo::calib_detail
