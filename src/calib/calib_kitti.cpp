// KITTI calibration: "P0: 12 numbers" ... "P3: ..." (the rectified 3x4
// projection matrices of the devkit's calib files), or calib_cam_to_cam's
// "P_rect_02:" / "P_rect_03:" (with "S_rect_02:" as the image size). The
// colour pair P2/P3 is used when present, else the gray pair P0/P1.
//
// With P = [f 0 cx f*tx; 0 f cy 0; 0 0 1 0] (t in metres), the baseline is the
// difference of the two f*tx over f, and doffs the difference of the cx.
#include <cmath>
#include <map>

#include "src/calib/calib_text.hpp"

namespace tristereo::calib_detail {

StereoCalibration read_kitti(const std::string& path, const std::vector<Line>& lines) {
  std::map<std::string, Line> kv;
  for (const Line& l : lines) {
    const std::string t = trim(l.text);
    const std::size_t colon = t.find(':');
    if (t.empty() || colon == std::string::npos) continue;
    kv[trim(t.substr(0, colon))] = {l.number, t.substr(colon + 1)};
  }
  const char* pairs[][2] = {{"P2", "P3"}, {"P_rect_02", "P_rect_03"}, {"P0", "P1"}, {"P_rect_00", "P_rect_01"}};
  const char* left_key = nullptr;
  const char* right_key = nullptr;
  for (const auto& p : pairs)
    if (kv.count(p[0]) && kv.count(p[1])) {
      left_key = p[0];
      right_key = p[1];
      break;
    }
  if (!left_key)
    fail(ErrorCode::kCorruptFile, path, 0, "P2/P3",
         "missing: a KITTI calibration needs the projection matrices P2 and P3 (or P0 and P1)");
  auto matrix34 = [&](const char* key) {
    const Line& l = kv[key];
    const std::vector<double> m = parse_numbers(l.text, path, l.number, key);
    if (m.size() != 12)
      fail(ErrorCode::kCorruptFile, path, l.number, key,
           "expected 12 numbers (a 3x4 projection matrix), got " + std::to_string(m.size()));
    return m;
  };
  const std::vector<double> pl = matrix34(left_key), pr = matrix34(right_key);
  StereoCalibration c;
  c.format = CalibFormat::kKitti;
  c.path = path;
  c.focal_px = pl[0];
  c.cx_px = pl[2];
  c.cy_px = pl[6];
  if (!(pl[0] > 0)) fail(ErrorCode::kInvalidArgument, path, kv[left_key].number, left_key, "focal length must be > 0");
  if (pr[0] != pl[0])
    fail(ErrorCode::kCorruptFile, path, kv[right_key].number, right_key,
         "focal length differs from " + std::string(left_key) + "'s: the pair is not rectified");
  c.baseline_m = (pl[3] - pr[3]) / pl[0];
  c.doffs_px = pr[2] - pl[2];
  const std::string size_key = std::string(left_key) == "P_rect_02" ? "S_rect_02" : "";
  if (!size_key.empty() && kv.count(size_key)) {
    const Line& l = kv[size_key];
    const std::vector<double> s = parse_numbers(l.text, path, l.number, size_key);
    if (s.size() != 2 || s[0] < 1 || s[1] < 1)
      fail(ErrorCode::kCorruptFile, path, l.number, size_key, "expected the image size 'width height'");
    c.width = static_cast<int>(std::lround(s[0]));
    c.height = static_cast<int>(std::lround(s[1]));
  }
  validate(c, kv[left_key].number, kv[right_key].number);
  return c;
}

}  // namespace tristereo::calib_detail
