// datasets.tsv: the scenes of a data set folder and their evaluation settings.
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tristereo/eval.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

namespace {

std::vector<std::string> split_tabs(const std::string& line) {
  std::vector<std::string> out;
  std::size_t start = 0;
  for (;;) {
    const std::size_t tab = line.find('\t', start);
    out.push_back(line.substr(start, tab == std::string::npos ? std::string::npos : tab - start));
    if (tab == std::string::npos) return out;
    start = tab + 1;
  }
}

int parse_int(const std::string& s, const std::string& path, int line_no, const char* column,
              int lo, int hi) {
  const auto fail = [&] {
    throw Error(ErrorCode::kCorruptFile, "'" + path + "' line " + std::to_string(line_no) + ": " +
                                             column + " '" + s + "' is not an integer in " +
                                             std::to_string(lo) + ".." + std::to_string(hi));
  };
  if (s.empty() || s.size() > 9 || s.find_first_not_of("0123456789") != std::string::npos) fail();
  const int v = std::stoi(s);
  if (v < lo || v > hi) fail();
  return v;
}

}  // namespace

std::vector<MiddleburyScene> read_datasets_tsv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(ErrorCode::kIoError, "cannot open '" + path + "'");
  std::string line;
  if (!std::getline(in, line)) throw Error(ErrorCode::kCorruptFile, "'" + path + "' is empty");
  if (!line.empty() && line.back() == '\r') line.pop_back();
  const std::vector<std::string> header = split_tabs(line);
  const char* names[5] = {"name", "width", "height", "ndisp", "gt_scale"};
  std::size_t col[5];
  for (int k = 0; k < 5; ++k) {
    col[k] = header.size();
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == names[k]) col[k] = i;
    if (col[k] == header.size()) {
      throw Error(ErrorCode::kCorruptFile,
                  "'" + path + "': header has no column '" + names[k] + "'");
    }
  }
  const auto optional_column = [&](const char* name) {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return i;
    return header.size();
  };
  const std::size_t opt_gt_file = optional_column("gt_file");
  const std::size_t opt_gt_format = optional_column("gt_format");
  const std::size_t opt_noc_mask = optional_column("noc_mask");
  std::vector<MiddleburyScene> scenes;
  int line_no = 1;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const std::vector<std::string> f = split_tabs(line);
    if (f.size() < header.size()) {
      throw Error(ErrorCode::kCorruptFile, "'" + path + "' line " + std::to_string(line_no) +
                                               ": " + std::to_string(f.size()) +
                                               " columns, header has " +
                                               std::to_string(header.size()));
    }
    MiddleburyScene s;
    s.name = f[col[0]];
    if (s.name.empty()) {
      throw Error(ErrorCode::kCorruptFile,
                  "'" + path + "' line " + std::to_string(line_no) + ": empty name");
    }
    s.width = parse_int(f[col[1]], path, line_no, "width", 1, 65535);
    s.height = parse_int(f[col[2]], path, line_no, "height", 1, 65535);
    s.ndisp = parse_int(f[col[3]], path, line_no, "ndisp", 1, 4096);
    s.gt_scale = parse_int(f[col[4]], path, line_no, "gt_scale", 1, 65535);
    if (opt_gt_file < header.size()) s.gt_file = f[opt_gt_file];
    if (opt_gt_format < header.size()) s.gt_format = f[opt_gt_format];
    if (opt_noc_mask < header.size()) s.noc_mask = f[opt_noc_mask];
    scenes.push_back(s);
  }
  return scenes;
}

}  // namespace tristereo
