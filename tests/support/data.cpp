#include "support/data.hpp"

#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <utility>

#include "tristereo/io.hpp"
#include "tristereo/status.hpp"

namespace tristereo::test {

std::string data_root() {
  // The environment may point elsewhere (data kept outside the checkout's
  // parent, or a test of this very rule); else the folder the build was
  // configured with.
  const char* env = std::getenv("TRISTEREO_DATA_DIR");
  return env != nullptr && *env != '\0' ? env : TRISTEREO_DATA_DIR;
}

std::string data_set_dir(const std::string& set) { return data_root() + "/" + set; }

bool data_set_available(const std::string& set) {
  // The unrectified sets (opencv-stereo-calib, euroc-v101) have no scenes
  // table: their calibration file is what a test needs.
  return std::ifstream(data_set_dir(set) + "/datasets.tsv").good() ||
         std::ifstream(data_set_dir(set) + "/calib_opencv.yml").good();
}

bool missing_data_allowed() {
  const char* allow = std::getenv("TRISTEREO_ALLOW_MISSING_DATA");
  return allow != nullptr && std::string(allow) == "1";
}

}  // namespace tristereo::test

namespace tristereo::test {

std::vector<std::string> data_set_names() {
  return {"middlebury", "middlebury2014", "kitti2015", "eth3d"};
}

const char* to_string(DataMetric m) {
  switch (m) {
    case DataMetric::kBad1: return "bad 1 px";
    case DataMetric::kBad2: return "bad 2 px";
    case DataMetric::kD1: return "D1";
  }
  return "?";
}

namespace {

// "| set/scene | metric | SGBM | BM | libelas |" rows of the data README.
struct PeerRow {
  double sgbm, bm, libelas;
};
std::map<std::string, PeerRow> read_readme_peers() {
  std::map<std::string, PeerRow> rows;
  std::ifstream in(data_root() + "/README.md");
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, '|')) {
      const std::size_t a = cell.find_first_not_of(' '), b = cell.find_last_not_of(' ');
      cells.push_back(a == std::string::npos ? "" : cell.substr(a, b - a + 1));
    }
    // cells[0] is the text before the first '|'.
    if (cells.size() != 6 || cells[1].find('/') == std::string::npos) continue;
    char* end[3];
    const double v[3] = {std::strtod(cells[3].c_str(), &end[0]), std::strtod(cells[4].c_str(), &end[1]),
                         std::strtod(cells[5].c_str(), &end[2])};
    if (*end[0] || *end[1] || *end[2] || cells[3].empty()) continue;
    rows[cells[1]] = {v[0], v[1], v[2]};
  }
  return rows;
}

}  // namespace

std::vector<DataScene> load_data_set(const std::string& set) {
  const std::string root = data_set_dir(set);
  const std::map<std::string, PeerRow> peers = read_readme_peers();
  std::vector<DataScene> out;
  for (const MiddleburyScene& row : read_datasets_tsv(root + "/datasets.tsv")) {
    DataScene s;
    s.set = set;
    s.name = row.name;
    s.dir = root + "/" + row.name;
    s.ndisp = row.ndisp;
    s.left = read_image_u8(s.dir + "/left.png");
    s.right = read_image_u8(s.dir + "/right.png");
    if (set == "middlebury") {  // v2: no gt_file column; fixed names (its README)
      s.gt = load_middlebury_gt(s.dir + "/disp_left.png", row.gt_scale);
      s.nonocc = read_image_u8(s.dir + "/nonocc.png");
      s.all = read_image_u8(s.dir + "/all.png");
      s.metric = DataMetric::kBad1;
      s.metric_on_nonocc = true;
    } else {
      DispFileFormat fmt = DispFileFormat::kPfm;
      if (row.gt_format == "kitti16") {
        fmt = DispFileFormat::kKitti;
      } else if (row.gt_format != "pfm") {
        throw Error(ErrorCode::kCorruptFile, root + "/datasets.tsv: scene " + row.name +
                                                 ": unknown gt_format '" + row.gt_format + "'");
      }
      s.gt = read_disparity_px(s.dir + "/" + row.gt_file, fmt, 1);
      if (!row.noc_mask.empty() && row.noc_mask != "none")
        s.nonocc = read_image_u8(s.dir + "/" + row.noc_mask);
      s.metric = set == "kitti2015" ? DataMetric::kD1 : DataMetric::kBad2;
    }
    const auto p = peers.find(set + "/" + row.name);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    s.peer_sgbm = p != peers.end() ? p->second.sgbm : nan;
    s.peer_bm = p != peers.end() ? p->second.bm : nan;
    s.peer_libelas = p != peers.end() ? p->second.libelas : nan;
    out.push_back(std::move(s));
  }
  return out;
}

std::vector<DataScene> load_all_data_scenes() {
  std::vector<DataScene> all;
  for (const std::string& set : data_set_names())
    for (DataScene& s : load_data_set(set)) all.push_back(std::move(s));
  return all;
}

double readme_score(const DataScene& scene, ImageView<const float> disp_px) {
  ImageView<const std::uint8_t> mask{};
  if (scene.metric_on_nonocc) mask = scene.nonocc.view();
  const BadPixelStats s = evaluate_disparity(disp_px, scene.gt.view(), mask);
  switch (scene.metric) {
    case DataMetric::kBad1: return s.bad_1;
    case DataMetric::kBad2: return s.bad_2;
    case DataMetric::kD1: return s.d1;
  }
  return 0;
}

}  // namespace tristereo::test
