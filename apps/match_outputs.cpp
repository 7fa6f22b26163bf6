#include "apps/match_outputs.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <utility>

#include "apps/option_errors.hpp"
#include "apps/output_paths.hpp"
#include "apps/output_set.hpp"
#include "tristereo/calib.hpp"
#include "tristereo/depth.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/status.hpp"
#include "tristereo/io.hpp"

namespace tristereo::cli {

namespace {
double ms(std::int64_t ns) { return static_cast<double>(ns) / 1e6; }

// --camera's bare baseline (no unit suffix) above this is refused as a likely
// unit mistake; with an explicit "m" the calibration bounds (calib.hpp) apply.
constexpr double kMaxBareBaselineM = 10.0;

CameraParams parse_camera(const std::string& text, bool* baseline_unit_given) {
  CameraParams c{};
  double v[5] = {0, 0, 0, 0, 0};
  std::stringstream ss(text);
  std::string item;
  int n = 0;
  *baseline_unit_given = false;
  while (std::getline(ss, item, ',')) {
    if (n >= 5) throw UsageError("--camera takes at most 5 numbers: F,B,CX,CY[,DOFFS]");
    if (n != 1) {
      v[n++] = parse_double("--camera", item);
      continue;
    }
    // The baseline may carry its unit: 0.12, 0.12m, 12cm, 120mm.
    const std::string given = item;
    double unit_m = 1.0;
    for (const auto& [suffix, metres] : {std::pair<const char*, double>{"mm", 0.001}, {"cm", 0.01}, {"m", 1.0}}) {
      const std::size_t len = std::char_traits<char>::length(suffix);
      if (item.size() > len && item.compare(item.size() - len, len, suffix) == 0) {
        item.resize(item.size() - len);
        unit_m = metres;
        *baseline_unit_given = true;
        break;
      }
    }
    try {
      v[n++] = parse_double("--camera", item) * unit_m;
    } catch (const UsageError&) {
      throw UsageError("--camera: baseline '" + given + "' is not a number of metres, or one followed by m, cm or mm");
    }
  }
  if (n < 4) throw UsageError("--camera needs F,B,CX,CY[,DOFFS]");
  c.focal_px = v[0];
  c.baseline = v[1];
  c.cx = v[2];
  c.cy = v[3];
  c.doffs = v[4];
  return c;
}
std::string lower_ext(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  const std::size_t slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string e = path.substr(dot);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

// Pixels of each state (a SampleState map).
struct StateCounts {
  long long measured = 0, filled = 0, invalid = 0;
};
StateCounts count_states(const ImageU8& state) {
  StateCounts c;
  for (std::uint8_t s : state.pixels) {
    if (s == static_cast<std::uint8_t>(SampleState::kMeasured)) ++c.measured;
    else if (s == static_cast<std::uint8_t>(SampleState::kFilled)) ++c.filled;
    else ++c.invalid;
  }
  return c;
}

// The disparities with every one whose state is not measured made invalid.
std::vector<std::int16_t> measured_only(const std::vector<std::int16_t>& disp_q4,
                                        const std::vector<std::uint8_t>& state) {
  std::vector<std::int16_t> out(disp_q4);
  for (std::size_t i = 0; i < out.size(); ++i)
    if (state[i] != static_cast<std::uint8_t>(SampleState::kMeasured)) out[i] = kInvalidDispQ4;
  return out;
}

// Bounding box of the valid pixels (ROS DisparityImage.valid_window).
struct Window {
  int x = 0, y = 0, w = 0, h = 0;
};
Window valid_window(const ImageS16& disp_q4) {
  int x0 = disp_q4.width, y0 = disp_q4.height, x1 = -1, y1 = -1;
  for (int y = 0; y < disp_q4.height; ++y)
    for (int x = 0; x < disp_q4.width; ++x)
      if (disp_q4.at(x, y) != kInvalidDispQ4) {
        x0 = std::min(x0, x);
        x1 = std::max(x1, x);
        y0 = std::min(y0, y);
        y1 = std::max(y1, y);
      }
  if (x1 < 0) return {};
  return {x0, y0, x1 - x0 + 1, y1 - y0 + 1};
}
}  // namespace

std::optional<CameraParams> camera_from_args(const Args& args, int width, int height,
                                             std::string* source) {
  const bool calib = args.has("calib"), camera = args.has("camera");
  if (calib && camera) throw UsageError("--calib and --camera both set the camera: give one of them");
  for (const char* opt : {"depth", "points"})
    if (args.has(opt) && !calib && !camera && !args.has("rig"))
      throw UsageError(std::string("--") + opt +
                       " needs a camera: --calib FILE (or --camera F,B,CX,CY[,DOFFS], or --rig FILE)");
  if (args.has("depth")) {
    const std::string e = lower_ext(args.get("depth", ""));
    if (e != ".pfm" && e != ".png")
      throw UsageError("--depth " + args.get("depth", "") + ": the file must end in .pfm (metres) or .png (uint16 millimetres)");
  }
  const std::string disp_format = args.get("disp-format", "q4");
  if (disp_format != "q4" && disp_format != "kitti")
    throw UsageError("--disp-format " + disp_format + ": expected q4 or kitti");
  if (args.has("disp-format") && lower_ext(args.get("disp", "")) != ".png")
    throw UsageError("--disp-format applies to a --disp .png file");
  if (args.has("points") && lower_ext(args.get("points", "")) != ".ply")
    throw UsageError("--points " + args.get("points", "") + ": the file must end in .ply");
  if (camera) {
    *source = "--camera";
    bool unit_given = false;
    const CameraParams c = parse_camera(args.get("camera", ""), &unit_given);
    // The bounds every calibration file is held to (calib.hpp), for this
    // input's size; refused now rather than after computing.
    if (const CameraBoundsCheck check = check_camera_bounds(c, width, height))
      throw UsageError("--camera: " + check.message + " (F,B,CX,CY,DOFFS: B in metres)");
    // A bare baseline is metres. Over 10 m is no robot's rig but a common slip:
    // a baseline copied in millimetres (Middlebury's files state it so).
    if (!unit_given && c.baseline > kMaxBareBaselineM) {
      char msg[300];
      std::snprintf(msg, sizeof msg,
                    "--camera: baseline %.6g is taken as metres, and over %g m is not a stereo rig's: "
                    "in millimetres it would be %.6g m; write the unit (e.g. %.6gmm or %.6gm)",
                    c.baseline, kMaxBareBaselineM, c.baseline / 1000.0, c.baseline, c.baseline / 1000.0);
      throw UsageError(msg);
    }
    return c;
  }
  if (!calib) return std::nullopt;
  CalibFormat format = CalibFormat::kAuto;
  try {
    format = parse_calib_format(args.get("calib-format", "auto"));
  } catch (const Error&) {
    throw UsageError("--calib-format " + args.get("calib-format", "") + ": expected auto, middlebury, kitti or opencv");
  }
  double unit_m = 1.0;
  const std::string unit = args.get("calib-unit", "m");
  if (unit == "m") unit_m = 1.0;
  else if (unit == "cm") unit_m = 0.01;
  else if (unit == "mm") unit_m = 0.001;
  else throw UsageError("--calib-unit " + unit + ": expected m, cm or mm");
  const StereoCalibration c = read_calibration(args.get("calib", ""), format, unit_m);
  // Middlebury and KITTI files state their unit; --calib-unit would silently
  // do nothing there, which hides a wrong belief about the file.
  if (args.has("calib-unit") && c.format != CalibFormat::kOpenCv)
    throw UsageError("--calib-unit " + unit + " has no effect: --calib " + c.path + " is a " + to_string(c.format) +
                     " calibration, whose unit is fixed (" +
                     (c.format == CalibFormat::kMiddlebury ? "baseline in millimetres" : "metres") +
                     "); --calib-unit applies to OpenCV files, which state none");
  check_calibration_size(c, width, height);
  // The file's bounds were checked for the size it states, if any; the
  // principal point must also make sense for the image it is used with.
  if (const CameraBoundsCheck check = check_camera_bounds(c.camera(), width, height))
    throw Error(ErrorCode::kInvalidArgument, "calibration file '" + c.path + "': " + check.message);
  if (c.format == CalibFormat::kOpenCv && !args.has("calib-unit") && c.baseline_m > 5)
    std::cerr << "warning: --calib " << c.path << ": the baseline comes out as " << c.baseline_m
              << " m; OpenCV files carry no unit: if the calibration target was measured in "
                 "millimetres, add --calib-unit mm\n";
  *source = c.path;
  return c.camera();
}

void write_samples_csv(const std::string& path, const StereoOutput& out) {
  std::ostringstream f;
  f << "x,y,disparity\n";
  for (std::size_t i = 0; i < out.mesh.vertices.size(); ++i) {
    const int16_t d = out.vertex_disp_q4[i];
    f << out.mesh.vertices[i].x << ',' << out.mesh.vertices[i].y << ',';
    if (d == kInvalidDispQ4)
      f << "inf\n";
    else
      f << d / 16.0 << '\n';
  }
  write_text_file(path, f.str());
}

std::string stats_json_text(const MatchRun& run) {
  const StereoOutput& o = run.out();
  const StateCounts counts = count_states(o.pixel_state);
  const StereoParams& p = run.config.params;
  const double pixels = static_cast<double>(o.mesh.width) * o.mesh.height;
  char buf[2560];
  std::snprintf(buf, sizeof buf,
                "{\n"
                "  \"implementation\": \"%s\",\n"
                "  \"threads\": %d,\n"
                "  \"width\": %d,\n  \"height\": %d,\n  \"ndisp\": %d,\n  \"dmin\": %d,\n"
                "  \"dense\": %s,\n"
                "  \"vertices\": %zu,\n  \"triangles\": %zu,\n"
                "  \"sample_fraction\": %.6f,\n"
                "  \"forced_splits\": %lld,\n  \"criterion_splits\": %lld,\n"
                "  \"params\": {\"psnr_db\": %.1f, \"max_area_px2\": %d, \"min_area_px2\": %d, \"window\": \"%dx%d\", "
                "\"weights\": \"%s\", \"truncation\": %d, \"lambda_q4\": %d, \"gap\": \"%s\", "
                "\"subpixel\": %s, \"subpixel_fit\": \"%s\", \"cost\": \"%s\", \"census\": \"%dx%d\", \"optimizer\": \"%s\", "
                "\"paths\": %d, \"p1_q4\": %d, \"p2_q4\": %d, \"p2_edge\": %d, \"lr_max_diff_q4\": %d, "
                "\"lr_source\": \"%s\", \"uniqueness_pct\": %d, \"fill\": \"%s\", \"support_prior\": %d},\n"
                "  \"validity\": {\"samples\": %d, \"uniqueness_rejected\": %d, \"lr_rejected\": %d, "
                "\"prior_redecided\": %d, \"prior_rejected\": %d, \"prior_recovered\": %d, \"prior_lost\": %d, "
                "\"invalid_fraction\": %.6f, \"filled\": %d, \"min_confidence\": %d, "
                "\"min_confidence_rejected\": %d},\n"
                "  \"pixels\": {\"measured\": %lld, \"filled\": %lld, \"invalid\": %lld},\n"
                "  \"ms\": {\"tritree\": %.3f, \"cost_aggregation\": %.3f, \"dp\": %.3f, \"prior\": %.3f, "
                "\"right_pass\": %.3f, \"fill\": %.3f, \"interpolation\": %.3f, \"total\": %.3f}\n"
                "}\n",
                run.implementation.c_str(), run.threads, o.mesh.width, o.mesh.height, p.num_disp,
                p.d_min, p.dense ? "true" : "false", o.mesh.vertices.size(), o.mesh.triangles.size(),
                pixels > 0 ? static_cast<double>(o.mesh.vertices.size()) / pixels : 0.0,
                static_cast<long long>(o.mesh.forced_splits),
                static_cast<long long>(o.mesh.criterion_splits), p.tritree.psnr_deci_db / 10.0,
                p.tritree.max_area_px2, p.tritree.min_area_px2, p.cost.window_w, p.cost.window_h, to_string(p.cost.weights),
                p.cost.truncation, p.dp.lambda_q4, to_string(p.dp.gap),
                p.dp.subpixel ? "true" : "false", to_string(p.dp.subpixel_fit), to_string(p.cost.kind),
                p.cost.census_w,
                p.cost.census_h, to_string(p.optimizer), p.paths.directions, p.paths.p1_q4,
                p.paths.p2_q4, p.paths.p2_edge_scale, p.validity.lr_max_diff_q4, to_string(p.validity.lr_source),
                p.validity.uniqueness_pct, to_string(p.validity.fill),
                support_prior_applies(p) ? p.prior.lambda_q4 : 0, o.validity.samples,
                o.validity.uniqueness_rejected, o.validity.lr_rejected, o.validity.prior_redecided,
                o.validity.prior_rejected, o.validity.prior_recovered, o.validity.prior_lost,
                o.validity.samples > 0
                    ? static_cast<double>(o.validity.uniqueness_rejected + o.validity.lr_rejected -
                                          o.validity.prior_recovered + o.validity.prior_lost) /
                          o.validity.samples
                    : 0.0,
                o.validity.filled, p.validity.min_confidence, o.validity.min_confidence_rejected,
                counts.measured, counts.filled, counts.invalid, ms(run.timings.tritree_ns),
                ms(run.timings.cost_aggregation_ns), ms(run.timings.dp_ns), ms(run.timings.prior_ns),
                ms(run.timings.right_pass_ns), ms(run.timings.fill_ns),
                ms(run.timings.interpolation_ns), ms(run.timings.total_ns));
  std::string text = buf;
  if (run.config.rectify) {  // raw frames: the rectification stage, part of "total"
    std::snprintf(buf, sizeof buf, ",\n  \"rectify_ms\": %.3f\n}\n", ms(run.timings.rectify_ns));
    text.resize(text.size() - 3);  // drop "\n}\n": the object goes on
    text += buf;
  }
  if (run.phases.read_inputs_ms >= 0) {
    std::snprintf(buf, sizeof buf,
                  ",\n  \"run_ms\": {\"read_inputs\": %.3f, \"configure\": %.3f, \"frame\": %.3f, "
                  "\"checks\": %.3f}\n}\n",
                  run.phases.read_inputs_ms, run.phases.configure_ms, run.phases.frame_ms, run.phases.checks_ms);
    text.resize(text.size() - 3);  // drop "\n}\n": the object goes on
    text += buf;
  }
  if (run.camera) {
    // The fields of a ROS stereo_msgs/DisparityImage for this frame.
    const Window w = valid_window(o.disp_q4);
    const CameraParams& c = *run.camera;
    std::snprintf(buf, sizeof buf,
                  ",\n  \"camera\": {\"source\": \"%s\", \"focal_px\": %.9g, \"baseline\": %.9g, "
                  "\"cx_px\": %.9g, \"cy_px\": %.9g, \"doffs_px\": %.9g},\n"
                  "  \"disparity_image\": {\"f\": %.9g, \"T\": %.9g, \"min_disparity\": %d, "
                  "\"max_disparity\": %d, \"delta_d\": 0.0625, \"valid_window\": {\"x_offset\": %d, "
                  "\"y_offset\": %d, \"width\": %d, \"height\": %d}, "
                  "\"invalid\": \"any disparity below min_disparity\", \"invalid_value\": %d, "
                  "\"invalid_pixels\": %lld}\n}\n",
                  run.camera_source.c_str(), c.focal_px, c.baseline, c.cx, c.cy, c.doffs, c.focal_px,
                  c.baseline, p.d_min, p.d_min + p.num_disp - 1, w.x, w.y, w.w, w.h, p.d_min - 1,
                  counts.invalid);
    text.resize(text.size() - 3);  // drop "\n}\n": the object goes on
    text += buf;
    // How many valid pixels the metric outputs leave out by the depth limits.
    ImageS16 limited = o.disp_q4;
    const std::int64_t beyond = apply_depth_limits(limited.view(), c, run.depth_limits);
    std::snprintf(buf, sizeof buf,
                  ",\n  \"depth_limits\": {\"min_disparity_px\": %.9g, \"min_depth_m\": %.9g, "
                  "\"max_depth_m\": %.9g, \"pixels_left_out\": %lld}\n}\n",
                  run.depth_limits.min_disparity_px, run.depth_limits.min_depth_m, run.depth_limits.max_depth_m,
                  static_cast<long long>(beyond));
    text.resize(text.size() - 3);
    text += buf;
  }
  return text;
}

void write_stats_json(const std::string& path, const MatchRun& run) { write_text_file(path, stats_json_text(run)); }

std::string stats_json_line(const MatchRun& run, int frame, const std::string& left, const std::string& right) {
  const std::string text = stats_json_text(run);
  // The same object on one line: each newline and the indent after it go;
  // the frame's index and its input files come first.
  std::string line = "{\"frame\": " + std::to_string(frame) + ", \"left\": " + json_string(left) +
                     ", \"right\": " + json_string(right) + ", ";
  line.reserve(line.size() + text.size());
  for (std::size_t i = 1; i < text.size(); ++i) {  // after the opening brace
    if (text[i] != '\n') {
      line += text[i];
      continue;
    }
    while (i + 1 < text.size() && text[i + 1] == ' ') ++i;
    if (i + 1 < text.size() && text[i + 1] == '}') line += ' ';
  }
  while (!line.empty() && line.back() == ' ') line.pop_back();
  return line;
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const char ch : s) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += ch;
    } else if (c < 0x20) {
      char esc[8];
      std::snprintf(esc, sizeof esc, "\\u%04x", c);
      out += esc;
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

void check_disp_output(const Args& args, const StereoParams& p) {
  if (!args.has("disp")) return;
  // What a 16-bit PNG cannot hold is refused before the computing.
  const std::string disp = args.get("disp", "");
  const bool png = disp.size() >= 4 && (disp.compare(disp.size() - 4, 4, ".png") == 0 ||
                                        disp.compare(disp.size() - 4, 4, ".PNG") == 0);
  if (png && p.d_min < 0)
    throw UsageError("--disp " + disp + ": a PNG cannot hold the negative disparities of --dmin " +
                     std::to_string(p.d_min) + "; write a .pfm file");
  if (png && args.get("disp-format", "q4") == "kitti" && p.d_min + p.num_disp - 1 >= 256)
    throw UsageError("--disp " + disp + " --disp-format kitti holds disparities below 256; --dmin + --ndisp - 1 is " +
                     std::to_string(p.d_min + p.num_disp - 1) + "; use q4 or a .pfm file");
}

DepthLimits depth_limits_from_args(const Args& args) {
  DepthLimits l;
  const auto value = [&](const char* opt, double fallback) {
    if (!args.has(opt)) return fallback;
    const std::string name = std::string("--") + opt;
    const double v = parse_double(name, args.get(opt, ""));
    if (v < 0) throw UsageError(name + " " + args.get(opt, "") + ": expected a value >= 0");
    return v;
  };
  l.min_disparity_px = value("min-disparity", l.min_disparity_px);
  l.min_depth_m = value("min-depth", l.min_depth_m);
  l.max_depth_m = value("max-depth", l.max_depth_m);
  if (args.has("max-depth") && !(l.max_depth_m > l.min_depth_m))
    throw UsageError("--max-depth " + args.get("max-depth", "") + " must be above --min-depth " +
                     (args.has("min-depth") ? args.get("min-depth", "") : std::string("(0)")));
  return l;
}

const std::vector<OutputOption>& match_output_options() {
  static const std::vector<OutputOption> kOutputs = {
      {"disp", {".pfm", ".png"}},   {"disp-color", {".png"}}, {"mesh", {".ply"}},
      {"depth", {".pfm", ".png"}},  {"points", {".ply"}},     {"samples", {".csv"}},
      {"stats", {".json"}},         {"valid", {".png"}},      {"confidence", {".png"}}};
  return kOutputs;
}

void write_match_outputs(const Args& args, const ImageU8& left, const MatchRun& run) {
  const StereoOutput& o = run.out();
  // All or nothing (output_set.hpp): staged in this order, renamed together.
  OutputSet outputs;
  if (args.has("disp"))
    outputs.add("--disp", args.get("disp", ""), [&](const std::string& path) {
      write_disparity(path, o.disp_q4.view(),
                      args.get("disp-format", "q4") == "kitti" ? DispPngScale::kKitti : DispPngScale::kQ4);
    });
  if (args.has("disp-color"))
    outputs.add("--disp-color", args.get("disp-color", ""), [&](const std::string& path) {
      write_disparity_color(path, o.disp_q4.view(), run.config.params.d_min, run.config.params.num_disp);
    });
  const CameraParams* cam = run.camera ? &*run.camera : nullptr;
  // --points and --mesh: measured pixels and vertices only, unless
  // --points-include-filled (a filled disparity is a neighbour's guess).
  const bool include_filled = args.flag("points-include-filled");
  std::vector<std::int16_t> mesh_disp;
  std::size_t faces_filled = 0;  // faces left out only because a vertex is filled
  if (args.has("mesh")) {
    mesh_disp = include_filled ? o.vertex_disp_q4 : measured_only(o.vertex_disp_q4, o.vertex_state);
    if (!include_filled) {
      for (const Triangle& t : o.mesh.triangles) {
        bool valid = true, measured = true;
        for (std::int32_t v : t) {
          valid = valid && o.vertex_disp_q4[static_cast<std::size_t>(v)] != kInvalidDispQ4;
          measured = measured && mesh_disp[static_cast<std::size_t>(v)] != kInvalidDispQ4;
        }
        if (valid && !measured) ++faces_filled;
      }
    }
  }
  // The metric outputs see the disparities within the depth limits only.
  std::int64_t vertices_beyond_limits = 0;
  const auto limit = [&](std::int16_t* values, int width, int height) {
    return width > 0 && height > 0
               ? apply_depth_limits({values, width, height, 1, static_cast<std::ptrdiff_t>(width) * 2}, *cam,
                                    run.depth_limits)
               : std::int64_t{0};
  };
  if (cam && args.has("mesh"))
    vertices_beyond_limits = limit(mesh_disp.data(), static_cast<int>(mesh_disp.size()), 1);
  MeshWriteReport mesh_report;
  if (args.has("mesh"))
    outputs.add("--mesh", args.get("mesh", ""), [&](const std::string& path) {
      mesh_report = write_mesh_ply(path, o.mesh, mesh_disp, left.view(), cam, !args.flag("mesh-ascii"));
    });
  ImageS16 depth_disp;
  if (args.has("depth") && cam) {
    depth_disp = o.disp_q4;
    limit(depth_disp.pixels.data(), depth_disp.width, depth_disp.height);
  }
  DepthWriteReport depth_report;
  if (args.has("depth") && cam)
    outputs.add("--depth", args.get("depth", ""), [&](const std::string& path) {
      depth_report = write_depth(path, depth_m_from_disp_q4(depth_disp.view(), *cam).view());
    });
  ImageS16 points_disp;
  if (args.has("points") && cam) {
    points_disp = o.disp_q4;
    if (!include_filled) points_disp.pixels = measured_only(o.disp_q4.pixels, o.pixel_state.pixels);
    limit(points_disp.pixels.data(), points_disp.width, points_disp.height);
  }
  if (args.has("points") && cam)
    outputs.add("--points", args.get("points", ""), [&](const std::string& path) {
      write_points_ply(path, points_disp.view(), left.view(), *cam, !args.flag("mesh-ascii"));
    });
  if (args.has("valid"))
    outputs.add("--valid", args.get("valid", ""),
                [&](const std::string& path) { write_png_u8(path, o.pixel_state.view()); });
  if (args.has("confidence"))
    outputs.add("--confidence", args.get("confidence", ""),
                [&](const std::string& path) { write_png_u8(path, o.pixel_confidence.view()); });
  if (args.has("samples"))
    outputs.add("--samples", args.get("samples", ""), [&](const std::string& path) { write_samples_csv(path, o); });
  if (args.has("stats"))
    outputs.add("--stats", args.get("stats", ""), [&](const std::string& path) { write_stats_json(path, run); });
  outputs.commit();

  // What the writers reported, once every output is in place.
  // Faces of filled vertices are left out by design (not a warning).
  const std::size_t without = mesh_report.faces_without_disparity - faces_filled;
  const std::size_t dropped = without + mesh_report.faces_behind_camera;
  if (dropped > 0) {
    std::cerr << "warning: --mesh " << args.get("mesh", "") << ": " << dropped << " of "
              << o.mesh.triangles.size() << " faces left out";
    if (without > 0) {
      std::cerr << "; " << without << " touch a vertex without a valid disparity";
      if (vertices_beyond_limits > 0)
        std::cerr << " or one of the " << vertices_beyond_limits
                  << " vertices outside the depth limits (d + doffs < --min-disparity "
                  << run.depth_limits.min_disparity_px
                  << " px, e.g. at or beyond infinity: check the camera's doffs and --dmin; or outside "
                     "--min-depth/--max-depth)";
    }
    if (mesh_report.faces_behind_camera > 0)
      std::cerr << "; " << mesh_report.faces_behind_camera
                << " touch a vertex at or beyond infinity (disparity + doffs <= 0: check the "
                   "camera's doffs and --dmin)";
    std::cerr << " (their vertices are still written, so indices match the mesh)\n";
  }
  if (depth_report.out_of_range > 0)
    std::cerr << "warning: --depth " << args.get("depth", "") << ": " << depth_report.out_of_range
              << " pixels are 65.535 m or farther and were written as 0 (invalid); use a .pfm file "
                 "to keep them\n";
}

void print_match_summary(std::ostream& os, const MatchRun& run) {
  const StereoOutput& o = run.out();
  const double pixels = static_cast<double>(o.mesh.width) * o.mesh.height;
  char buf[1024];
  std::snprintf(buf, sizeof buf,
                "%dx%d, D=%d (%s, %s): %zu vertices (%.2f%% of pixels), %zu triangles, "
                "%lld forced splits\n"
                "time: tritree %.2f ms, cost aggregation %.2f ms, %s %.2f ms, support prior %.2f ms, "
                "right view %.2f ms, fill %.2f ms, interpolation %.2f ms, total %.2f ms\n"
                "invalid samples: %d by uniqueness, %d by the left-right check (of %d); the support prior "
                "chose %d again (%d invalid ones got a disparity, %d valid ones lost theirs); %d filled; "
                "%d below the minimum confidence\n",
                o.mesh.width, o.mesh.height, run.config.params.num_disp, run.implementation.c_str(),
                run.config.params.dense ? "dense" : "sparse", o.mesh.vertices.size(),
                100.0 * static_cast<double>(o.mesh.vertices.size()) / pixels,
                o.mesh.triangles.size(), static_cast<long long>(o.mesh.forced_splits),
                ms(run.timings.tritree_ns), ms(run.timings.cost_aggregation_ns),
                run.config.params.optimizer == Optimizer::kPaths ? "paths" : "dp", ms(run.timings.dp_ns),
                ms(run.timings.prior_ns), ms(run.timings.right_pass_ns), ms(run.timings.fill_ns),
                ms(run.timings.interpolation_ns), ms(run.timings.total_ns),
                o.validity.uniqueness_rejected, o.validity.lr_rejected, o.validity.samples,
                o.validity.prior_redecided, o.validity.prior_recovered, o.validity.prior_lost,
                o.validity.filled, o.validity.min_confidence_rejected);
  os << buf;
  if (run.config.rectify) os << "rectification (raw frames in): " << ms(run.timings.rectify_ns) << " ms of the total\n";
}

}  // namespace tristereo::cli
