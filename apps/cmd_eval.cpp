// tristereo eval DISP GT [...]: bad-pixel rates and KITTI's D1 against a ground truth.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "apps/cli_args.hpp"
#include "apps/commands.hpp"
#include "apps/output_set.hpp"
#include "apps/output_paths.hpp"
#include "tristereo/eval.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/io.hpp"
#include "tristereo/status.hpp"

namespace tristereo::cli {

namespace {

const char* kEvalHelp = R"(usage: tristereo eval DISP GT [--gt-scale S] [--disp-scale S] [--gt-format F]
                     [--disp-format F] [--mask M.png] [--samples S.csv] [--json OUT.json]

Scores the disparity map DISP against the ground truth GT: the percentage of pixels
with known ground truth whose error exceeds 0.5, 1, 2 and 3 px, and KITTI's D1 (error
> 3 px and > 5 % of the ground truth); a pixel without a disparity counts as bad.
Also the end-point error (epe: the mean |d - gt| in px) and the RMS error of the
pixels that have a disparity, with the count of those that have none beside them.

  --gt-format F, --disp-format F   how the file encodes disparities:
        auto   (default) from the file: PFM; 8-bit PNG = png8; 16-bit PNG = kitti
               for GT, q4 for DISP
        pfm    float PFM in pixels, +inf = unknown / invalid (Middlebury 2014, ETH3D,
               match --disp X.pfm)
        png8   8-bit gray PNG, disparity = value / scale (Middlebury v2 ground truth)
        q4     16-bit PNG, value / 16, 0 = invalid (match --disp X.png)
        kitti  16-bit PNG, value / 256, 0 = unknown (KITTI disp_occ_0.png,
               match --disp X.png --disp-format kitti)
  --gt-scale S, --disp-scale S     the scale of an 8-bit PNG (1..255, default 1;
        Middlebury v2: the gt_scale of datasets.tsv)
  --mask M.png  score only pixels where M is 255 (Middlebury v2 nonocc.png, 2014
        mask0nocc.png: 255 non-occluded, 128 occluded, 0 no ground truth);
        without it, every pixel with known ground truth
  --samples S.csv  also score the sample positions written by match --samples
  --json OUT.json  also write every number as JSON

Warnings on stderr when the numbers are probably meaningless: the ground truth is
about k times the disparity (a wrong --gt-scale or format), or DISP looks like a
ground truth (holes, float values) and GT like a matcher's output (complete, on the
1/16 px grid): DISP and GT swapped.

)";

struct MapSource {
  const char* role;        // "DISP" or "GT"
  const char* fmt_option;  // "--disp-format" / "--gt-format"
  const char* scale_option;
  std::string path;
  DispFileFormat format = DispFileFormat::kPfm;
  int scale = 1;
};

int scale_from_args(const Args& args, const char* name) {
  const int s = args.get_int(name, 1);
  if (s < 1 || s > 255) {
    throw UsageError(std::string("--") + name + " " + std::to_string(s) +
                     ": expected an integer in 1..255");
  }
  return s;
}

// Resolves the format (explicit or from the file) and reads the map; errors
// name the role and the option, never an internal function.
Image<float> load_map(const Args& args, MapSource& src, const char* fmt_name, const char* scale_name,
                      DispFileFormat png16_default) {
  const std::string fmt = args.get(fmt_name, "auto");
  const bool explicit_format = fmt != "auto";
  if (explicit_format && !parse_disp_file_format(fmt, &src.format)) {
    throw UsageError(std::string(src.fmt_option) + " " + fmt +
                     ": expected auto, pfm, png8, q4 or kitti");
  }
  src.scale = scale_from_args(args, scale_name);
  try {
    if (!explicit_format) src.format = detect_disp_file_format(src.path, png16_default);
    if (args.has(scale_name) && src.format != DispFileFormat::kPng8) {
      std::cerr << "warning: " << src.scale_option << " " << src.scale << " ignored: " << src.role
                << " '" << src.path << "' is read as " << to_string(src.format)
                << " (the scale applies to 8-bit PNGs only)\n";
    }
    return read_disparity_px(src.path, src.format, src.scale);
  } catch (const Error& e) {
    std::string hint;
    if (e.code() == ErrorCode::kUnsupportedFormat && explicit_format)
      hint = " (" + std::string(src.fmt_option) + " " + fmt + "; try " + src.fmt_option + " auto)";
    throw Error(e.code(), std::string(src.role) + ": " + e.what() + hint);
  }
}

ImageU8 load_mask(const std::string& path, const Image<float>& gt) {
  ImageU8 mask;
  try {
    mask = read_image_u8(path);
  } catch (const Error& e) {
    if (e.code() == ErrorCode::kUnsupportedFormat)
      throw Error(e.code(), "--mask '" + path + "': expected an 8-bit gray PNG or PGM (255 = scored)");
    throw Error(e.code(), std::string("--mask: ") + e.what());
  }
  if (mask.channels != 1)
    throw Error(ErrorCode::kUnsupportedFormat,
                "--mask '" + path + "' is a colour image; expected 8-bit gray (255 = scored)");
  if (mask.width != gt.width || mask.height != gt.height)
    throw Error(ErrorCode::kSizeMismatch, "--mask '" + path + "' is " + std::to_string(mask.width) +
                                              "x" + std::to_string(mask.height) +
                                              ", the ground truth is " + std::to_string(gt.width) +
                                              "x" + std::to_string(gt.height));
  return mask;
}

double parse_sample_number(const std::string& path, int line_no, const std::string& text) {
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || errno != 0 || !std::isfinite(v))
    throw Error(ErrorCode::kCorruptFile, "--samples '" + path + "' line " + std::to_string(line_no) +
                                             ": '" + text + "' is not a number");
  return v;
}

void read_samples(const std::string& path, std::vector<Vertex>& pts, std::vector<std::int16_t>& d) {
  std::ifstream f(path);
  if (!f) throw Error(ErrorCode::kIoError, "--samples: cannot open '" + path + "'");
  std::string line;
  std::getline(f, line);
  if (line.rfind("x,y,disparity", 0) != 0)
    throw Error(ErrorCode::kCorruptFile,
                "--samples '" + path + "': expected a 'x,y,disparity' header (match --samples)");
  int line_no = 1;
  while (std::getline(f, line)) {
    ++line_no;
    if (line.empty()) continue;
    std::stringstream ss(line);
    std::string xs, ys, ds;
    if (!std::getline(ss, xs, ',') || !std::getline(ss, ys, ',') || !std::getline(ss, ds))
      throw Error(ErrorCode::kCorruptFile,
                  "--samples '" + path + "' line " + std::to_string(line_no) + ": expected x,y,disparity");
    const double x = parse_sample_number(path, line_no, xs), y = parse_sample_number(path, line_no, ys);
    if (x != std::floor(x) || y != std::floor(y) || std::fabs(x) > 65535 || std::fabs(y) > 65535)
      throw Error(ErrorCode::kCorruptFile, "--samples '" + path + "' line " + std::to_string(line_no) +
                                               ": x and y must be pixel coordinates");
    Vertex v;
    v.x = static_cast<int>(x);
    v.y = static_cast<int>(y);
    pts.push_back(v);
    if (ds == "inf") {
      d.push_back(kInvalidDispQ4);
    } else {
      const double q = parse_sample_number(path, line_no, ds) * kDispOne;
      if (!(std::fabs(q) < 32000))
        throw Error(ErrorCode::kCorruptFile, "--samples '" + path + "' line " +
                                                 std::to_string(line_no) + ": disparity out of range");
      d.push_back(static_cast<std::int16_t>(std::lround(q)));
    }
  }
}

void print_stats(const char* label, const BadPixelStats& s) {
  std::printf("%-8s bad>0.5: %6.2f%%  bad>1: %6.2f%%  bad>2: %6.2f%%  bad>3: %6.2f%%  D1: %6.2f%%  "
              "epe: %.3f px  rms: %.3f px  (%lld px, %lld invalid)\n",
              label, s.bad_0_5, s.bad_1, s.bad_2, s.bad_3, s.d1, s.epe, s.rms,
              static_cast<long long>(s.evaluated), static_cast<long long>(s.invalid));
}

std::string stats_json(const BadPixelStats& s) {
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "{\"bad_0_5\": %.4f, \"bad_1\": %.4f, \"bad_2\": %.4f, \"bad_3\": %.4f, \"d1\": %.4f, "
                "\"epe\": %.4f, \"rms\": %.4f, \"evaluated\": %lld, \"invalid\": %lld}",
                s.bad_0_5, s.bad_1, s.bad_2, s.bad_3, s.d1, s.epe, s.rms,
                static_cast<long long>(s.evaluated), static_cast<long long>(s.invalid));
  return buf;
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char b[8];
      std::snprintf(b, sizeof b, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
      out += b;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

}  // namespace

int cmd_eval(int argc, char** argv) {
  Args args(argc, argv, {"gt-scale", "disp-scale", "disp-format", "gt-format", "mask", "samples", "json"},
            {"help"});
  if (args.flag("help")) {
    std::cout << kEvalHelp << exit_codes_help();
    return 0;
  }
  if (args.positional().size() != 2) {
    throw UsageError("eval needs exactly two files, DISP and GT; got " +
                     std::to_string(args.positional().size()) + " (see --help)");
  }
  MapSource disp_src{"DISP", "--disp-format", "--disp-scale", args.positional()[0]};
  MapSource gt_src{"GT", "--gt-format", "--gt-scale", args.positional()[1]};
  // The output is checked before anything is read (extension, not an input, folder writable).
  check_output_paths(args, {{"json", {".json"}}},
                     {{"DISP", disp_src.path}, {"GT", gt_src.path}, {"--mask", args.get("mask", "")},
                      {"--samples", args.get("samples", "")}});

  const Image<float> disp = load_map(args, disp_src, "disp-format", "disp-scale", DispFileFormat::kQ4);
  const Image<float> gt = load_map(args, gt_src, "gt-format", "gt-scale", DispFileFormat::kKitti);
  if (disp.width != gt.width || disp.height != gt.height)
    throw Error(ErrorCode::kSizeMismatch, "DISP '" + disp_src.path + "' is " +
                                              std::to_string(disp.width) + "x" +
                                              std::to_string(disp.height) + " but GT '" +
                                              gt_src.path + "' is " + std::to_string(gt.width) +
                                              "x" + std::to_string(gt.height));
  ImageU8 mask;
  ImageView<const std::uint8_t> mask_view{};
  if (args.has("mask")) {
    mask = load_mask(args.get("mask", ""), gt);
    mask_view = mask.view();
  }
  std::vector<Vertex> sample_pts;  // read before anything is printed: a bad file prints no score
  std::vector<std::int16_t> sample_disp;
  if (args.has("samples")) read_samples(args.get("samples", ""), sample_pts, sample_disp);
  const BadPixelStats dense = evaluate_disparity(disp.view(), gt.view(), mask_view);
  print_stats("dense", dense);

  // Warnings: the numbers above are printed anyway (they are what was asked),
  // the hint says why they are probably meaningless.
  std::vector<std::string> warnings;
  const EvalInputCheck check = check_eval_inputs(disp.view(), gt.view());
  char buf[512];
  if (dense.evaluated == 0) {
    warnings.push_back(args.has("mask") ? "no pixel has known ground truth inside --mask (mask value 255)"
                                        : "GT has no pixel with known ground truth");
  }
  if (files_look_swapped(check)) {
    std::snprintf(buf, sizeof buf,
                  "DISP and GT look swapped (usage: tristereo eval DISP GT): DISP has holes at "
                  "%.2f%% of its pixels and %.0f%% of its values off the 1/16 px grid, like a "
                  "ground truth; GT has holes at %.2f%% and every value on the grid, like a "
                  "matcher's output",
                  100.0 * static_cast<double>(check.disp_none) / static_cast<double>(check.pixels),
                  100.0 * static_cast<double>(check.disp_off_q4_grid) /
                      static_cast<double>(check.pixels - check.disp_none),
                  100.0 * static_cast<double>(check.gt_unknown) / static_cast<double>(check.pixels));
    warnings.push_back(buf);
  }
  if (scale_looks_wrong(check)) {
    const double r = check.median_gt_over_disp;
    std::snprintf(buf, sizeof buf,
                  "GT is about %.3g times DISP at the median pixel (%.1f%% bad at 2 px): a scale is "
                  "probably wrong; DISP was read as %s",
                  r, dense.bad_2, to_string(disp_src.format));
    std::string w = buf;
    if (disp_src.format == DispFileFormat::kPng8) w += " / " + std::to_string(disp_src.scale);
    w += std::string(", GT as ") + to_string(gt_src.format);
    if (gt_src.format == DispFileFormat::kPng8) w += " / " + std::to_string(gt_src.scale);
    if (gt_src.format == DispFileFormat::kPng8 && r > 1.5) {
      w += "; try --gt-scale " + std::to_string(static_cast<long>(std::lround(gt_src.scale * r)));
    } else if (disp_src.format == DispFileFormat::kPng8 && r < 1 / 1.5) {
      w += "; DISP looks like an 8-bit ground truth: are DISP and GT swapped? (or try --disp-scale " +
           std::to_string(static_cast<long>(std::lround(disp_src.scale / r))) + ")";
    } else if (std::fabs(r - 16) < 2 || std::fabs(r - 1 / 16.0) < 0.01) {
      w += "; a 16-bit PNG is q4 (value / 16) or kitti (value / 256): try the other --gt-format / "
           "--disp-format";
    }
    if (r < 1 / 1.5 && check.disp_none > check.gt_unknown)
      w += "; DISP has more holes than GT: are DISP and GT swapped?";
    warnings.push_back(w);
  }
  for (const std::string& w : warnings) std::cerr << "warning: " << w << "\n";

  std::string json = "{\n  \"disp_format\": \"" + std::string(to_string(disp_src.format)) +
                     "\",\n  \"gt_format\": \"" + to_string(gt_src.format) + "\",\n";
  std::snprintf(buf, sizeof buf,
                "  \"pixels\": %lld,\n  \"disp_none\": %lld,\n  \"gt_unknown\": %lld,\n"
                "  \"disp_off_q4_grid\": %lld,\n  \"gt_off_q4_grid\": %lld,\n"
                "  \"median_gt_over_disp\": %.6g,\n",
                static_cast<long long>(check.pixels), static_cast<long long>(check.disp_none),
                static_cast<long long>(check.gt_unknown), static_cast<long long>(check.disp_off_q4_grid),
                static_cast<long long>(check.gt_off_q4_grid), check.median_gt_over_disp);
  json += buf;
  json += "  \"warnings\": [";
  for (std::size_t i = 0; i < warnings.size(); ++i) json += (i ? ", " : "") + json_string(warnings[i]);
  json += "],\n  \"dense\": " + stats_json(dense);
  if (args.has("samples")) {
    BadPixelStats at;
    try {
      at = evaluate_at_points(gt.view(), sample_pts, sample_disp, mask_view);
    } catch (const Error& e) {
      throw Error(e.code(), "--samples '" + args.get("samples", "") +
                                "' does not fit the ground truth (a sample outside the image, or "
                                "another pair's samples)");
    }
    print_stats("samples", at);
    json += ",\n  \"samples\": " + stats_json(at);
  }
  json += "\n}\n";
  // Through the helper every command's outputs take (output_set.hpp): the
  // same staging, and errors that name --json.
  OutputSet outputs;
  if (args.has("json"))
    outputs.add("--json", args.get("json", ""), [&json](const std::string& path) { write_text_file(path, json); });
  outputs.commit();
  return 0;
}

}  // namespace tristereo::cli
