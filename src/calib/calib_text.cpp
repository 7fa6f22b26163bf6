#include "src/calib/calib_text.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace tristereo::calib_detail {

std::vector<Line> read_lines(const std::string& path) {
  errno = 0;
  std::ifstream f(path, std::ios::binary);
  if (!f)
    throw Error(ErrorCode::kIoError, "calibration file '" + path + "': cannot open it" +
                                         (errno ? std::string(": ") + std::strerror(errno) : std::string()));
  // Read at most one byte past the limit, whatever the file claims: a stream
  // such as /dev/zero has no size to ask for and no end.
  std::string all(static_cast<std::size_t>(kMaxCalibBytes) + 1, '\0');
  f.read(&all[0], static_cast<std::streamsize>(all.size()));
  if (f.bad()) throw Error(ErrorCode::kIoError, "calibration file '" + path + "': cannot read it");
  all.resize(static_cast<std::size_t>(f.gcount()));
  if (all.size() > static_cast<std::size_t>(kMaxCalibBytes))
    throw Error(ErrorCode::kUnsupportedFormat,
                "calibration file '" + path + "': more than " + std::to_string(kMaxCalibBytes) +
                    " bytes, not a calibration file");
  if (all.find('\0') != std::string::npos)
    throw Error(ErrorCode::kUnsupportedFormat,
                "calibration file '" + path + "': holds NUL bytes, not a text calibration file");
  // A UTF-8 byte-order mark, which Windows editors put at the start of a
  // text file, is not part of the first key.
  if (all.compare(0, 3, "\xEF\xBB\xBF") == 0) all.erase(0, 3);
  std::vector<Line> lines;
  std::istringstream in(all);
  std::string text;
  int n = 0;
  while (std::getline(in, text)) {
    if (!text.empty() && text.back() == '\r') text.pop_back();
    lines.push_back({++n, text});
  }
  return lines;
}

std::string trim(const std::string& s) {
  const std::size_t b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  const std::size_t e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

void fail(ErrorCode code, const std::string& path, int line, const std::string& key,
          const std::string& what) {
  std::string where = "calibration file '" + path + "'";
  if (line > 0) where += ", line " + std::to_string(line);
  if (!key.empty()) where += ", key '" + key + "'";
  throw Error(code, where + ": " + what);
}

std::vector<double> parse_numbers(const std::string& text, const std::string& path, int line,
                                  const std::string& key) {
  std::vector<double> out;
  std::string token;
  auto flush = [&] {
    if (token.empty()) return;
    char* end = nullptr;
    const double v = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0' || !std::isfinite(v))
      fail(ErrorCode::kCorruptFile, path, line, key, "'" + token + "' is not a finite number");
    out.push_back(v);
    token.clear();
  };
  for (char ch : text) {
    if (ch == ' ' || ch == '\t' || ch == '\n' || ch == '\r' || ch == ';' || ch == ',' || ch == '[' || ch == ']') {
      flush();
    } else {
      token += ch;
    }
  }
  flush();
  return out;
}

void validate(const StereoCalibration& c, int line_of_focal, int line_of_baseline) {
  if (c.width < 0 || c.height < 0)
    fail(ErrorCode::kInvalidArgument, c.path, 0, "width/height", "image size must be >= 0");
  // The same bounds as --camera (calib.hpp): a focal length or a baseline in
  // the wrong unit, or a typo, gives depths of 0 or infinity everywhere.
  const CameraBoundsCheck check = check_camera_bounds(c.camera(), c.width, c.height);
  switch (check.field) {
    case CameraField::kNone: return;
    case CameraField::kFocal: fail(ErrorCode::kInvalidArgument, c.path, line_of_focal, "focal length", check.message);
    case CameraField::kBaseline: fail(ErrorCode::kInvalidArgument, c.path, line_of_baseline, "baseline", check.message);
    case CameraField::kPrincipalPoint:
      fail(ErrorCode::kInvalidArgument, c.path, line_of_focal, "principal point", check.message);
    case CameraField::kDoffs: fail(ErrorCode::kInvalidArgument, c.path, 0, "doffs", check.message);
  }
}

}  // namespace tristereo::calib_detail
