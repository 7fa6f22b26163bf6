// OpenCV stereo calibration written by cv::FileStorage (YAML "%YAML:1.0" or
// XML "<opencv_storage>"), holding stereoRectify's outputs: P1 and P2 (the
// rectified 3x4 projection matrices), or Q (the 4x4 reprojection matrix).
//
//   P1 = [f 0 cx1 0; 0 f cy 0; 0 0 1 0], P2 = [f 0 cx2 Tx*f; 0 f cy 0; 0 0 1 0]
//   Q  = [1 0 0 -cx1; 0 1 0 -cy; 0 0 0 f; 0 0 -1/Tx (cx1 - cx2)/Tx]
// so baseline = -Tx, doffs = cx2 - cx1. Tx is in the units of the calibration
// target (OpenCV stores none): opencv_unit_m converts it to metres.
// The image size is read from image_width/image_height or imageSize/image_size
// ([width, height]) when the file has them.
#include <cmath>
#include <map>

#include "src/calib/calib_text.hpp"

namespace tristereo::calib_detail {

namespace {

using Node = StorageNode;

int parse_int(const std::string& text, const std::string& path, int line, const std::string& key) {
  const std::vector<double> v = parse_numbers(text, path, line, key);
  if (v.size() != 1 || v[0] != std::floor(v[0]) || v[0] < 0 || v[0] > 1e6)
    fail(ErrorCode::kCorruptFile, path, line, key, "expected a whole number, got '" + trim(text) + "'");
  return static_cast<int>(v[0]);
}

std::map<std::string, Node> parse_yaml(const std::string& path, const std::vector<Line>& lines) {
  std::map<std::string, Node> nodes;
  Node* current = nullptr;
  bool in_data = false;
  for (const Line& l : lines) {
    const std::string t = trim(l.text);
    if (t.empty() || t[0] == '%' || t == "---" || t[0] == '#') continue;
    const bool top = l.text[0] != ' ' && l.text[0] != '\t';
    if (in_data && current) {  // a data sequence continues until its ']'
      current->text += " " + t;
      if (t.find(']') != std::string::npos) in_data = false;
      continue;
    }
    const std::size_t colon = t.find(':');
    if (colon == std::string::npos)
      fail(ErrorCode::kCorruptFile, path, l.number, "", "expected 'key: value', got '" + t + "'");
    const std::string key = trim(t.substr(0, colon));
    const std::string value = trim(t.substr(colon + 1));
    if (top) {
      Node& n = nodes[key];
      n = Node{};
      n.line = l.number;
      n.matrix = value.find("!!opencv-matrix") != std::string::npos;
      if (!n.matrix) n.text = value;
      current = &n;
      if (!n.matrix && value.find('[') != std::string::npos && value.find(']') == std::string::npos)
        in_data = true;
    } else if (current && current->matrix) {
      if (key == "rows") current->rows = parse_int(value, path, l.number, key);
      else if (key == "cols") current->cols = parse_int(value, path, l.number, key);
      else if (key == "data") {
        current->text = value;
        in_data = value.find(']') == std::string::npos;
      }
    }
  }
  if (in_data) fail(ErrorCode::kCorruptFile, path, 0, "data", "a data sequence has no closing ']'");
  return nodes;
}

std::map<std::string, Node> parse_xml(const std::string& path, const std::vector<Line>& lines) {
  std::string all;
  std::vector<int> line_of;  // line number of each character
  for (const Line& l : lines) {
    all += l.text + "\n";
    line_of.insert(line_of.end(), l.text.size() + 1, l.number);
  }
  const std::size_t root = all.find("<opencv_storage>");
  const std::size_t root_end = all.find("</opencv_storage>");
  if (root == std::string::npos || root_end == std::string::npos)
    fail(ErrorCode::kCorruptFile, path, 0, "opencv_storage", "missing or unclosed <opencv_storage>");
  std::map<std::string, Node> nodes;
  std::size_t pos = root + 16;
  // Top-level elements: <name ...> body </name>; nested tags only inside matrices.
  while (true) {
    const std::size_t open = all.find('<', pos);
    if (open == std::string::npos || open >= root_end) break;
    if (all.compare(open, 4, "<!--") == 0) {
      const std::size_t e = all.find("-->", open);
      if (e == std::string::npos) fail(ErrorCode::kCorruptFile, path, line_of[open], "", "unclosed comment");
      pos = e + 3;
      continue;
    }
    const std::size_t name_end = all.find_first_of(" \t\n>/", open + 1);
    const std::size_t tag_end = all.find('>', open);
    if (name_end == std::string::npos || tag_end == std::string::npos)
      fail(ErrorCode::kCorruptFile, path, line_of[open], "", "unclosed tag");
    const std::string name = all.substr(open + 1, name_end - open - 1);
    const std::string close = "</" + name + ">";
    const std::size_t body_end = all.find(close, tag_end);
    if (body_end == std::string::npos)
      fail(ErrorCode::kCorruptFile, path, line_of[open], name, "no closing " + close);
    const std::string head = all.substr(open, tag_end - open);
    const std::string body = all.substr(tag_end + 1, body_end - tag_end - 1);
    Node n;
    n.line = line_of[open];
    n.matrix = head.find("opencv-matrix") != std::string::npos;
    if (n.matrix) {
      auto child = [&](const char* tag) {
        const std::string o = std::string("<") + tag + ">", c = std::string("</") + tag + ">";
        const std::size_t a = body.find(o), b = body.find(c);
        if (a == std::string::npos || b == std::string::npos || b < a)
          fail(ErrorCode::kCorruptFile, path, n.line, name, std::string("matrix without <") + tag + ">");
        return body.substr(a + o.size(), b - a - o.size());
      };
      n.rows = parse_int(child("rows"), path, n.line, name + ".rows");
      n.cols = parse_int(child("cols"), path, n.line, name + ".cols");
      n.text = child("data");
    } else {
      n.text = body;
    }
    nodes[name] = n;
    pos = body_end + close.size();
  }
  return nodes;
}

std::vector<double> matrix(const std::map<std::string, Node>& nodes, const std::string& key, int rows,
                           int cols, const std::string& path) {
  const Node& n = nodes.at(key);
  if (!n.matrix) fail(ErrorCode::kCorruptFile, path, n.line, key, "is not an opencv-matrix");
  if (n.rows != rows || n.cols != cols)
    fail(ErrorCode::kCorruptFile, path, n.line, key,
         "expected " + std::to_string(rows) + "x" + std::to_string(cols) + ", the file says " +
             std::to_string(n.rows) + "x" + std::to_string(n.cols));
  const std::vector<double> m = parse_numbers(n.text, path, n.line, key);
  if (m.size() != static_cast<std::size_t>(rows * cols))
    fail(ErrorCode::kCorruptFile, path, n.line, key,
         "expected " + std::to_string(rows * cols) + " numbers in data, got " + std::to_string(m.size()));
  return m;
}

}  // namespace

std::map<std::string, StorageNode> read_opencv_storage(const std::string& path, const std::vector<Line>& lines) {
  for (const Line& l : lines)
    if (l.text.find("<opencv_storage>") != std::string::npos) return parse_xml(path, lines);
  return parse_yaml(path, lines);
}

StereoCalibration read_opencv_file(const std::string& path, const std::vector<Line>& lines,
                                   double unit_m) {
  const std::map<std::string, Node> nodes = read_opencv_storage(path, lines);
  StereoCalibration c;
  c.format = CalibFormat::kOpenCv;
  c.path = path;
  int focal_line = 0, baseline_line = 0;
  if (nodes.count("P1") && nodes.count("P2")) {
    const std::vector<double> p1 = matrix(nodes, "P1", 3, 4, path), p2 = matrix(nodes, "P2", 3, 4, path);
    if (p1[0] != p2[0])
      fail(ErrorCode::kCorruptFile, path, nodes.at("P2").line, "P2",
           "focal length differs from P1's: not the output of stereoRectify");
    c.focal_px = p1[0];
    c.cx_px = p1[2];
    c.cy_px = p1[6];
    c.doffs_px = p2[2] - p1[2];
    if (p1[0] > 0) c.baseline_m = (p1[3] - p2[3]) / p1[0] * unit_m;
    focal_line = nodes.at("P1").line;
    baseline_line = nodes.at("P2").line;
  } else if (nodes.count("Q")) {
    const std::vector<double> q = matrix(nodes, "Q", 4, 4, path);
    c.focal_px = q[11];
    c.cx_px = -q[3];
    c.cy_px = -q[7];
    if (q[14] == 0) fail(ErrorCode::kInvalidArgument, path, nodes.at("Q").line, "Q", "Q(3,2) = -1/Tx is 0");
    c.baseline_m = 1.0 / q[14] * unit_m;
    c.doffs_px = q[15] / q[14];
    focal_line = baseline_line = nodes.at("Q").line;
  } else {
    fail(ErrorCode::kCorruptFile, path, 0, "P1/P2",
         "missing: an OpenCV stereo calibration needs P1 and P2, or Q (stereoRectify's outputs)");
  }
  auto size_of = [&](const std::string& key) {
    const Node& n = nodes.at(key);
    return parse_int(n.text, path, n.line, key);
  };
  if (nodes.count("image_width") && nodes.count("image_height")) {
    c.width = size_of("image_width");
    c.height = size_of("image_height");
  } else {
    for (const char* key : {"imageSize", "image_size"})
      if (nodes.count(key)) {
        const Node& n = nodes.at(key);
        const std::vector<double> s = parse_numbers(n.text, path, n.line, key);
        if (s.size() != 2 || s[0] < 1 || s[1] < 1 || s[0] > 65535 || s[1] > 65535)
          fail(ErrorCode::kCorruptFile, path, n.line, key, "expected [width, height]");
        c.width = static_cast<int>(s[0]);
        c.height = static_cast<int>(s[1]);
      }
  }
  validate(c, focal_line, baseline_line);
  return c;
}

}  // namespace tristereo::calib_detail
