// The subset of YAML that camera calibration files use (ROS camera_info,
// Kalibr camchain, EuRoC sensor.yaml): nested block mappings by indentation,
// block sequences ("- item"), scalars, and flow sequences ("[1, 2, 3]", which
// may span lines). Tags (!!opencv-matrix), anchors and multi-document files
// are not needed by these formats and are refused or ignored as noted.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "src/calib/calib_text.hpp"

namespace tristereo::calib_detail {

struct YamlNode {
  enum Kind { kScalar, kMap, kSeq } kind = kScalar;
  int line = 0;
  std::string text;                                      // kScalar: the value (a flow sequence as written)
  std::vector<std::pair<std::string, YamlNode>> fields;  // kMap, in file order
  std::vector<YamlNode> items;                           // kSeq

  const YamlNode* find(const std::string& key) const;
};

// The document's root mapping. Fails (kCorruptFile, naming file and line) on
// lines that are neither "key: value" nor "- item" where one is expected, bad
// indentation and unclosed flow sequences.
YamlNode parse_yaml_tree(const std::string& path, const std::vector<Line>& lines);

// Accessors failing with file, line and key ("where" is the key path shown,
// e.g. "cam1/T_cn_cnm1").
const YamlNode& yaml_get(const YamlNode& map, const std::string& key, const std::string& path,
                         const std::string& where);
// Every number of a scalar, flow sequence or sequence of them, in order.
std::vector<double> yaml_numbers(const YamlNode& node, const std::string& path, const std::string& where);
// yaml_numbers with exactly `count` numbers.
std::vector<double> yaml_numbers(const YamlNode& node, std::size_t count, const std::string& path,
                                 const std::string& where);
// A scalar without quotes.
std::string yaml_string(const YamlNode& node, const std::string& path, const std::string& where);

}  // namespace tristereo::calib_detail
