#include "apps/match_outputs.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>

#include "tristereo/fixed_point.hpp"
#include "tristereo/status.hpp"
#include "tristereo/io.hpp"

namespace tristereo::cli {

namespace {
double ms(std::int64_t ns) { return static_cast<double>(ns) / 1e6; }

std::ofstream open_out(const std::string& path) {
  std::ofstream f(path);
  if (!f) throw Error(ErrorCode::kIoError, "cannot write '" + path + "'");
  return f;
}

CameraParams parse_camera(const std::string& text) {
  CameraParams c{};
  double v[5] = {0, 0, 0, 0, 0};
  std::stringstream ss(text);
  std::string item;
  int n = 0;
  while (std::getline(ss, item, ',')) {
    if (n >= 5) throw UsageError("--camera takes at most 5 numbers: F,B,CX,CY[,DOFFS]");
    v[n++] = parse_double("--camera", item);
  }
  if (n < 4) throw UsageError("--camera needs F,B,CX,CY[,DOFFS]");
  if (!(v[0] > 0) || !(v[1] > 0)) throw UsageError("--camera: focal length and baseline must be > 0");
  c.focal_px = v[0];
  c.baseline = v[1];
  c.cx = v[2];
  c.cy = v[3];
  c.doffs = v[4];
  return c;
}
}  // namespace

void write_samples_csv(const std::string& path, const StereoOutput& out) {
  std::ofstream f = open_out(path);
  f << "x,y,disparity\n";
  for (std::size_t i = 0; i < out.mesh.vertices.size(); ++i) {
    const int16_t d = out.vertex_disp_q4[i];
    f << out.mesh.vertices[i].x << ',' << out.mesh.vertices[i].y << ',';
    if (d == kInvalidDispQ4)
      f << "inf\n";
    else
      f << d / 16.0 << '\n';
  }
}

void write_stats_json(const std::string& path, const MatchRun& run) {
  const StereoOutput& o = run.output;
  const StereoParams& p = run.config.params;
  const double pixels = static_cast<double>(o.mesh.width) * o.mesh.height;
  std::ofstream f = open_out(path);
  char buf[2048];
  std::snprintf(buf, sizeof buf,
                "{\n"
                "  \"implementation\": \"%s\",\n"
                "  \"threads\": %d,\n"
                "  \"width\": %d,\n  \"height\": %d,\n  \"ndisp\": %d,\n  \"dmin\": %d,\n"
                "  \"dense\": %s,\n"
                "  \"vertices\": %zu,\n  \"triangles\": %zu,\n"
                "  \"sample_fraction\": %.6f,\n"
                "  \"forced_splits\": %lld,\n  \"criterion_splits\": %lld,\n"
                "  \"params\": {\"psnr_db\": %.1f, \"max_area_px2\": %d, \"window\": \"%dx%d\", "
                "\"weights\": \"%s\", \"truncation\": %d, \"lambda_q4\": %d, \"gap\": \"%s\", "
                "\"subpixel\": %s},\n"
                "  \"ms\": {\"tritree\": %.3f, \"cost_aggregation\": %.3f, \"dp\": %.3f, "
                "\"interpolation\": %.3f, \"total\": %.3f}\n"
                "}\n",
                run.implementation.c_str(), run.threads, o.mesh.width, o.mesh.height, p.num_disp,
                p.d_min, p.dense ? "true" : "false", o.mesh.vertices.size(), o.mesh.triangles.size(),
                pixels > 0 ? static_cast<double>(o.mesh.vertices.size()) / pixels : 0.0,
                static_cast<long long>(o.mesh.forced_splits),
                static_cast<long long>(o.mesh.criterion_splits), p.tritree.psnr_deci_db / 10.0,
                p.tritree.max_area_px2, p.cost.window_w, p.cost.window_h, to_string(p.cost.weights),
                p.cost.truncation, p.dp.lambda_q4, to_string(p.dp.gap),
                p.dp.subpixel ? "true" : "false", ms(run.timings.tritree_ns),
                ms(run.timings.cost_aggregation_ns), ms(run.timings.dp_ns),
                ms(run.timings.interpolation_ns), ms(run.timings.total_ns));
  f << buf;
  if (!f) throw Error(ErrorCode::kIoError, "error writing '" + path + "'");
}

void write_match_outputs(const Args& args, const ImageU8& left, const MatchRun& run) {
  const StereoOutput& o = run.output;
  if (args.has("disp")) write_disparity(args.get("disp", ""), o.disp_q4.view());
  if (args.has("disp-color"))
    write_disparity_color(args.get("disp-color", ""), o.disp_q4.view(), run.config.params.d_min,
                          run.config.params.num_disp);
  if (args.has("mesh")) {
    CameraParams cam{};
    const bool have_cam = args.has("camera");
    if (have_cam) cam = parse_camera(args.get("camera", ""));
    write_mesh_ply(args.get("mesh", ""), o.mesh, o.vertex_disp_q4, left.view(),
                   have_cam ? &cam : nullptr, !args.flag("mesh-ascii"));
  }
  if (args.has("samples")) write_samples_csv(args.get("samples", ""), o);
  if (args.has("stats")) write_stats_json(args.get("stats", ""), run);
}

void print_match_summary(std::ostream& os, const MatchRun& run) {
  const StereoOutput& o = run.output;
  const double pixels = static_cast<double>(o.mesh.width) * o.mesh.height;
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "%dx%d, D=%d (%s, %s): %zu vertices (%.2f%% of pixels), %zu triangles, "
                "%lld forced splits\n"
                "time: tritree %.2f ms, cost aggregation %.2f ms, dp %.2f ms, interpolation %.2f "
                "ms, total %.2f ms\n",
                o.mesh.width, o.mesh.height, run.config.params.num_disp, run.implementation.c_str(),
                run.config.params.dense ? "dense DP" : "sparse DP", o.mesh.vertices.size(),
                100.0 * static_cast<double>(o.mesh.vertices.size()) / pixels,
                o.mesh.triangles.size(), static_cast<long long>(o.mesh.forced_splits),
                ms(run.timings.tritree_ns), ms(run.timings.cost_aggregation_ns), ms(run.timings.dp_ns),
                ms(run.timings.interpolation_ns), ms(run.timings.total_ns));
  os << buf;
}

}  // namespace tristereo::cli
