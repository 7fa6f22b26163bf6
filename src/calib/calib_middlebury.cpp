// Middlebury calib.txt: "key=value" lines (spaces anywhere), cam0/cam1 as
// "[f 0 cx; 0 f cy; 0 0 1]", doffs in pixels, baseline in millimetres.
#include <cmath>
#include <map>

#include "src/calib/calib_text.hpp"

namespace tristereo::calib_detail {

StereoCalibration read_middlebury(const std::string& path, const std::vector<Line>& lines) {
  std::map<std::string, Line> kv;
  for (const Line& l : lines) {
    const std::string t = trim(l.text);
    if (t.empty()) continue;
    const std::size_t eq = t.find('=');
    if (eq == std::string::npos)
      fail(ErrorCode::kCorruptFile, path, l.number, "", "expected 'key=value', got '" + t + "'");
    kv[trim(t.substr(0, eq))] = {l.number, t.substr(eq + 1)};
  }
  auto need = [&](const char* key) -> const Line& {
    auto it = kv.find(key);
    if (it == kv.end()) fail(ErrorCode::kCorruptFile, path, 0, key, "missing (a Middlebury calib.txt has it)");
    return it->second;
  };
  auto matrix3 = [&](const char* key) {
    const Line& l = need(key);
    const std::vector<double> m = parse_numbers(l.text, path, l.number, key);
    if (m.size() != 9)
      fail(ErrorCode::kCorruptFile, path, l.number, key,
           "expected a 3x3 matrix [f 0 cx; 0 f cy; 0 0 1], got " + std::to_string(m.size()) + " numbers");
    return m;
  };
  auto scalar = [&](const char* key) {
    const Line& l = need(key);
    const std::vector<double> v = parse_numbers(l.text, path, l.number, key);
    if (v.size() != 1) fail(ErrorCode::kCorruptFile, path, l.number, key, "expected one number");
    return v[0];
  };
  auto size = [&](const char* key) {
    if (!kv.count(key)) return 0;
    const double v = scalar(key);
    if (v < 1 || v > 65535 || v != std::floor(v))
      fail(ErrorCode::kCorruptFile, path, kv[key].number, key, "expected a whole number of pixels");
    return static_cast<int>(v);
  };

  StereoCalibration c;
  c.format = CalibFormat::kMiddlebury;
  c.path = path;
  const std::vector<double> cam0 = matrix3("cam0");
  c.focal_px = cam0[0];
  c.cx_px = cam0[2];
  c.cy_px = cam0[5];
  if (kv.count("doffs")) {
    c.doffs_px = scalar("doffs");
  } else {
    const std::vector<double> cam1 = matrix3("cam1");
    c.doffs_px = cam1[2] - cam0[2];
  }
  c.baseline_m = scalar("baseline") / 1000.0;  // Middlebury states millimetres
  c.width = size("width");
  c.height = size("height");
  validate(c, need("cam0").number, need("baseline").number);
  return c;
}

}  // namespace tristereo::calib_detail
