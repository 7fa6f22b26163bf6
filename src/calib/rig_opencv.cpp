// OpenCV's stereo calibration, as stereo_calib.cpp and most tutorials save it
// with cv::FileStorage (YAML or XML): M1 D1 M2 D2 (each camera's matrix and
// distortion), R T (p_right = R p_left + T), the image size as
// image_width/image_height or imageSize, and stereoRectify's R1 R2 P1 P2 when
// present. D has 4, 5, 8, 12 or 14 entries (OpenCV's order); 4 or 5 are the
// radial-tangential model, 8 or more the rational one.
#include <cmath>

#include "src/calib/rig_readers.hpp"

namespace tristereo::calib_detail {

namespace {

using Nodes = std::map<std::string, StorageNode>;

std::vector<double> matrix(const Nodes& nodes, const std::string& key, int rows, int cols, const std::string& path) {
  const auto it = nodes.find(key);
  if (it == nodes.end()) fail(ErrorCode::kCorruptFile, path, 0, key, "missing");
  const StorageNode& n = it->second;
  if (!n.matrix) fail(ErrorCode::kCorruptFile, path, n.line, key, "is not an opencv-matrix");
  // A vector may be stored as a row or as a column.
  const bool fits = (n.rows == rows && n.cols == cols) || (cols == 0 && (n.rows == 1 || n.cols == 1)) ||
                    (rows == 1 && n.rows == cols && n.cols == 1) || (cols == 1 && n.cols == rows && n.rows == 1);
  if (!fits)
    fail(ErrorCode::kCorruptFile, path, n.line, key,
         (cols == 0 ? std::string("expected a vector") : "expected " + std::to_string(rows) + "x" + std::to_string(cols)) +
             ", the file says " + std::to_string(n.rows) + "x" + std::to_string(n.cols));
  const std::vector<double> m = parse_numbers(n.text, path, n.line, key);
  if (m.size() != static_cast<std::size_t>(n.rows) * static_cast<std::size_t>(n.cols))
    fail(ErrorCode::kCorruptFile, path, n.line, key,
         "expected " + std::to_string(n.rows * n.cols) + " numbers in data, got " + std::to_string(m.size()));
  return m;
}

int line_of(const Nodes& nodes, const std::string& key) {
  const auto it = nodes.find(key);
  return it == nodes.end() ? 0 : it->second.line;
}

template <std::size_t N>
std::array<double, N> to_array(const std::vector<double>& v) {
  std::array<double, N> a{};
  for (std::size_t i = 0; i < N; ++i) a[i] = v[i];
  return a;
}

}  // namespace

StereoRig read_rig_opencv(const std::string& path, const std::vector<Line>& lines, double unit_m) {
  const Nodes nodes = read_opencv_storage(path, lines);
  StereoRig rig;
  RigOrigins at;
  RawCamera* cams[2] = {&rig.left, &rig.right};
  for (int c = 0; c < 2; ++c) {
    const std::string m = c == 0 ? "M1" : "M2", d = c == 0 ? "D1" : "D2";
    cams[c]->K = to_array<9>(matrix(nodes, m, 3, 3, path));
    const std::vector<double> dist = matrix(nodes, d, 1, 0, path);
    const Origin dist_at{path, line_of(nodes, d), d};
    set_distortion(*cams[c], dist.size() <= 5 ? DistortionModel::kRadTan : DistortionModel::kRational, dist, dist_at);
    at.k[c] = {path, line_of(nodes, m), m};
    at.dist[c] = dist_at;
  }
  rig.R = to_array<9>(matrix(nodes, "R", 3, 3, path));
  const std::vector<double> t = matrix(nodes, "T", 3, 1, path);
  for (int i = 0; i < 3; ++i) rig.T[static_cast<std::size_t>(i)] = t[static_cast<std::size_t>(i)] * unit_m;
  at.rotation = {path, line_of(nodes, "R"), "R"};
  at.translation = {path, line_of(nodes, "T"), "T"};

  auto whole = [&](const std::string& key) {
    const StorageNode& n = nodes.at(key);
    const std::vector<double> v = parse_numbers(n.text, path, n.line, key);
    if (v.size() != 1) fail(ErrorCode::kCorruptFile, path, n.line, key, "expected one number");
    return v[0];
  };
  Origin size_at;
  if (nodes.count("image_width") && nodes.count("image_height")) {
    size_at = {path, line_of(nodes, "image_width"), "image_width"};
    set_size(rig.left, whole("image_width"), whole("image_height"), size_at);
  } else if (nodes.count("imageSize") || nodes.count("image_size")) {
    const std::string key = nodes.count("imageSize") ? "imageSize" : "image_size";
    const StorageNode& n = nodes.at(key);
    const std::vector<double> s = parse_numbers(n.text, path, n.line, key);
    size_at = {path, n.line, key};
    if (s.size() != 2) fail(ErrorCode::kCorruptFile, path, n.line, key, "expected [width, height]");
    set_size(rig.left, s[0], s[1], size_at);
  } else {
    fail(ErrorCode::kCorruptFile, path, 0, "image_width/image_height",
         "missing: the image size the cameras were calibrated at (image_width and image_height, or imageSize)");
  }
  rig.right.width = rig.left.width;
  rig.right.height = rig.left.height;
  at.size[0] = at.size[1] = size_at;

  const bool any = nodes.count("R1") || nodes.count("R2") || nodes.count("P1") || nodes.count("P2");
  if (any) {
    rig.R1 = to_array<9>(matrix(nodes, "R1", 3, 3, path));
    rig.R2 = to_array<9>(matrix(nodes, "R2", 3, 3, path));
    rig.P1 = to_array<12>(matrix(nodes, "P1", 3, 4, path));
    rig.P2 = to_array<12>(matrix(nodes, "P2", 3, 4, path));
    for (std::size_t i : {3u, 7u, 11u}) rig.P2[i] *= unit_m;
    rig.has_rectification = true;
  }
  validate_rig(rig, at);
  return rig;
}

}  // namespace tristereo::calib_detail
