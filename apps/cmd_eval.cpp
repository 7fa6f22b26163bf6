// tristereo eval DISP GT [--gt-scale S] [--mask M] [--samples S.csv]: Middlebury-style scores.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include "apps/cli_args.hpp"
#include "apps/commands.hpp"
#include "tristereo/eval.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/status.hpp"
#include "tristereo/io.hpp"

namespace tristereo::cli {

namespace {
// A disparity or ground-truth file as float pixels. format: "auto" (PFM by
// its magic bytes, an 8-bit PNG as value / scale, a 16-bit PNG as Q4, what
// `match --disp X.png` writes), "pfm", "png8", "q4" or "kitti" (value / 256).
Image<float> load_disparity_any(const std::string& path, int scale, const std::string& format,
                                const char* option) {
  if (format != "auto" && format != "pfm" && format != "png8" && format != "q4" && format != "kitti")
    throw UsageError(std::string(option) + " " + format + ": expected auto, pfm, png8, q4 or kitti");
  std::string kind = format;
  if (kind == "auto") {
    std::ifstream f(path, std::ios::binary);
    char magic[26] = {};
    f.read(magic, sizeof magic);
    if (f.gcount() >= 2 && magic[0] == 'P' && (magic[1] == 'f' || magic[1] == 'F')) {
      kind = "pfm";
    } else if (f.gcount() >= 25 && std::string(magic + 1, 3) == "PNG") {
      kind = static_cast<unsigned char>(magic[24]) == 16 ? "q4" : "png8";  // IHDR bit depth
    } else {
      kind = "png8";  // let the reader name what is wrong with it
    }
  }
  if (kind == "pfm") return read_pfm(path);
  if (kind == "png8") return load_middlebury_gt(path, scale);
  const Image<std::int16_t> q4 =
      read_disparity(path, kind == "kitti" ? DispPngScale::kKitti : DispPngScale::kQ4);
  return disp_q4_to_float(q4.view());
}

void print_stats(const char* label, const BadPixelStats& s) {
  std::printf("%-10s bad>0.5: %6.2f%%  bad>1: %6.2f%%  bad>2: %6.2f%%  rms: %.3f px  (%lld px, %lld invalid)\n",
              label, s.bad_0_5, s.bad_1, s.bad_2, s.rms, static_cast<long long>(s.evaluated),
              static_cast<long long>(s.invalid));
}

std::string stats_json(const BadPixelStats& s) {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "{\"bad_0_5\": %.4f, \"bad_1\": %.4f, \"bad_2\": %.4f, \"rms\": %.4f, "
                "\"evaluated\": %lld, \"invalid\": %lld}",
                s.bad_0_5, s.bad_1, s.bad_2, s.rms, static_cast<long long>(s.evaluated),
                static_cast<long long>(s.invalid));
  return buf;
}

void read_samples(const std::string& path, std::vector<Vertex>& pts, std::vector<std::int16_t>& d) {
  std::ifstream f(path);
  if (!f) throw Error(ErrorCode::kIoError, "cannot read '" + path + "'");
  std::string line;
  std::getline(f, line);
  if (line.rfind("x,y,disparity", 0) != 0)
    throw Error(ErrorCode::kCorruptFile, path + ": expected a 'x,y,disparity' header (tristereo match --samples)");
  int line_no = 1;
  while (std::getline(f, line)) {
    ++line_no;
    if (line.empty()) continue;
    std::stringstream ss(line);
    std::string xs, ys, ds;
    if (!std::getline(ss, xs, ',') || !std::getline(ss, ys, ',') || !std::getline(ss, ds))
      throw Error(ErrorCode::kCorruptFile, path + ":" + std::to_string(line_no) + ": expected x,y,disparity");
    Vertex v;
    v.x = parse_int("samples x", xs);
    v.y = parse_int("samples y", ys);
    pts.push_back(v);
    if (ds == "inf") {
      d.push_back(kInvalidDispQ4);
    } else {
      const double q = parse_double("samples disparity", ds) * 16.0;
      if (!(std::fabs(q) < 32000)) throw Error(ErrorCode::kCorruptFile, path + ": disparity out of range");
      d.push_back(static_cast<std::int16_t>(std::lround(q)));
    }
  }
}
}  // namespace

int cmd_eval(int argc, char** argv) {
  Args args(argc, argv, {"gt-scale", "disp-scale", "disp-format", "gt-format", "mask", "samples", "json"},
            {"help"});
  if (args.flag("help")) {
    std::cout << "usage: tristereo eval DISP GT [--gt-scale S] [--disp-scale S] [--disp-format F]\n"
                 "                     [--gt-format F] [--mask M.png] [--samples S.csv] [--json OUT.json]\n\n"
                 "Bad-pixel percentages (|d - gt| > 0.5, 1, 2 px; invalid counts as bad) and RMS,\n"
                 "Middlebury v2 style. DISP: PFM (+inf = invalid), 8-bit PNG (value / --disp-scale)\n"
                 "or 16-bit PNG (0 = invalid). GT: the same, 0 or +inf = unknown, skipped.\n"
                 "--disp-format/--gt-format auto|pfm|png8|q4|kitti: auto (default) reads PFM and 8-bit\n"
                 "PNG by their contents and a 16-bit PNG as q4 (value / 16: match --disp X.png);\n"
                 "kitti reads a 16-bit PNG as value / 256 (KITTI, match --disp-format kitti).\n"
                 "--mask: only pixels where the mask is 255 (e.g. Middlebury nonocc.png).\n"
                 "--samples: also score only the sample positions written by match --samples\n"
                 "(the paper's Table 2 metric).\n"
                 "--json OUT.json: also write the numbers as JSON.\n";
    return 0;
  }
  if (args.positional().size() != 2) throw UsageError("eval needs DISP and GT (see --help)");
  const int gt_scale = args.get_int("gt-scale", 1);
  const int disp_scale = args.get_int("disp-scale", 1);
  if (gt_scale < 1 || disp_scale < 1) throw UsageError("--gt-scale and --disp-scale must be >= 1");
  const Image<float> disp =
      load_disparity_any(args.positional()[0], disp_scale, args.get("disp-format", "auto"), "--disp-format");
  const Image<float> gt =
      load_disparity_any(args.positional()[1], gt_scale, args.get("gt-format", "auto"), "--gt-format");
  if (disp.width != gt.width || disp.height != gt.height)
    throw Error(ErrorCode::kSizeMismatch, "disparity and ground truth differ in size");
  ImageU8 mask;
  if (args.has("mask")) {
    mask = read_image_u8(args.get("mask", ""));
    if (mask.width != gt.width || mask.height != gt.height || mask.channels != 1)
      throw Error(ErrorCode::kSizeMismatch, "mask must be a gray image of the ground truth's size");
  }
  ImageView<const std::uint8_t> mask_view{};
  if (args.has("mask")) mask_view = mask.view();
  const BadPixelStats dense = evaluate_disparity(disp.view(), gt.view(), mask_view);
  print_stats("dense", dense);
  std::string json = "{\n  \"dense\": " + stats_json(dense);
  if (args.has("samples")) {
    std::vector<Vertex> pts;
    std::vector<std::int16_t> d;
    read_samples(args.get("samples", ""), pts, d);
    const BadPixelStats at = evaluate_at_points(gt.view(), pts, d, mask_view);
    print_stats("samples", at);
    json += ",\n  \"samples\": " + stats_json(at);
  }
  json += "\n}\n";
  if (args.has("json")) {
    std::ofstream f(args.get("json", ""));
    f << json;
    if (!f) throw Error(ErrorCode::kIoError, "cannot write '" + args.get("json", "") + "'");
  }
  return 0;
}

}  // namespace tristereo::cli
