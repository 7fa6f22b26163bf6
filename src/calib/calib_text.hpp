// Small text helpers shared by the calibration readers: every error they raise
// names the file, the line and the key, as the bad-input policy asks.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "tristereo/calib.hpp"
#include "tristereo/status.hpp"

namespace tristereo::calib_detail {

// Largest calibration file read (they are a few hundred bytes; a bigger file
// is not a calibration and is refused before it is read whole).
constexpr long long kMaxCalibBytes = 1 << 20;

struct Line {
  int number;        // 1-based
  std::string text;  // without the line end
};

// The file's lines; kIoError when it cannot be read, kUnsupportedFormat when
// it is larger than kMaxCalibBytes.
std::vector<Line> read_lines(const std::string& path);

std::string trim(const std::string& s);

// "<path>:<line>: key '<key>': <what>" (line 0 = no line).
[[noreturn]] void fail(ErrorCode code, const std::string& path, int line, const std::string& key,
                       const std::string& what);

// Parses every whitespace/;/,-separated number of `text` (brackets ignored);
// a token that is not a finite number fails naming it.
std::vector<double> parse_numbers(const std::string& text, const std::string& path, int line,
                                  const std::string& key);

// The checks shared by every format: size >= 0, and every value within the
// physical bounds of check_camera_bounds (calib.hpp) for the size the file
// states, failing with the line of the focal length (cx, cy too) or the baseline.
void validate(const StereoCalibration& c, int line_of_focal, int line_of_baseline);

StereoCalibration read_middlebury(const std::string& path, const std::vector<Line>& lines);
StereoCalibration read_kitti(const std::string& path, const std::vector<Line>& lines);
// A top-level entry of a cv::FileStorage file (YAML or XML).
struct StorageNode {
  int line = 0;
  int rows = 0, cols = 0;   // matrices only
  std::string text;         // scalars and sequences: the value; matrices: the data
  bool matrix = false;
};
// The top-level entries of a cv::FileStorage file, by name.
std::map<std::string, StorageNode> read_opencv_storage(const std::string& path, const std::vector<Line>& lines);

StereoCalibration read_opencv_file(const std::string& path, const std::vector<Line>& lines,
                                   double unit_m);

}  // namespace tristereo::calib_detail
