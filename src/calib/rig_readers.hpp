// The raw-rig readers (one file per format) and what they share: every
// error names the file, the line and the key (calib_text.hpp's fail()).
#pragma once

#include <string>
#include <vector>

#include "src/calib/calib_text.hpp"
#include "src/calib/yaml_tree.hpp"
#include "tristereo/rig.hpp"

namespace tristereo::calib_detail {

// Where a value came from, for the messages of validate_rig.
struct Origin {
  std::string path;
  int line = 0;
  std::string key;
};

struct RigOrigins {
  Origin k[2];     // each camera's intrinsics
  Origin dist[2];  // each camera's distortion coefficients
  Origin size[2];  // each camera's image size
  Origin rotation, translation;
};
// The cameras' origins of a rig read from one file per camera (ROS, EuRoC):
// any two records with Origin members k, dist and size.
template <class CameraFile>
RigOrigins camera_origins(const CameraFile& left, const CameraFile& right) {
  RigOrigins at;
  at.k[0] = left.k;
  at.k[1] = right.k;
  at.dist[0] = left.dist;
  at.dist[1] = right.dist;
  at.size[0] = left.size;
  at.size[1] = right.size;
  return at;
}

// "plumb_bob", "radtan", "radial-tangential" -> kRadTan; "rational_polynomial"
// -> kRational; "equidistant", "fisheye" -> kEquidistant; fails otherwise.
DistortionModel distortion_model_named(const std::string& name, const Origin& at);
// Stores the coefficients of `model`, failing on a count the model does not
// have (kRadTan: 4 or 5, kRational: 8, or OpenCV's 12/14 with the thin-prism
// and tilt terms 0; kEquidistant: 4).
void set_distortion(RawCamera& cam, DistortionModel model, const std::vector<double>& coeffs, const Origin& at);
// K from fx, fy, cx, cy.
std::array<double, 9> pinhole(double fx, double fy, double cx, double cy);
// An image size "w h", whole numbers in 2 .. kMaxReadSide.
void set_size(RawCamera& cam, double w, double h, const Origin& at);

// The bounds of every format: focal lengths and principal points as
// check_camera_bounds() for the camera's size, K's last row (0 0 1), R a
// rotation (orthonormal to 1e-6, determinant +1), |T| within the baseline
// bounds, both cameras the same size, distortion coefficients within +-1e4.
void validate_rig(const StereoRig& rig, const RigOrigins& at);

StereoRig read_rig_opencv(const std::string& path, const std::vector<Line>& lines, double unit_m);
StereoRig read_rig_ros(const std::string& left, const YamlNode& l, const std::string& right, const YamlNode& r,
                       double unit_m);
StereoRig read_rig_kalibr(const std::string& path, const YamlNode& root);
StereoRig read_rig_euroc(const std::string& left, const YamlNode& l, const std::string& right, const YamlNode& r);

}  // namespace tristereo::calib_detail
