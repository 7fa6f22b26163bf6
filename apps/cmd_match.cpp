// tristereo match LEFT RIGHT --ndisp D [...]: one pair -> disparity, mesh, stats.
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>

#include "apps/cli_args.hpp"
#include "apps/commands.hpp"
#include "apps/stereo_options.hpp"
#include "apps/match_outputs.hpp"
#include "tristereo/io.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/reference.hpp"
#include "tristereo/status.hpp"

namespace tristereo::cli {

namespace {
const char* kMatchHelp = R"(usage: tristereo match LEFT RIGHT --ndisp D [options]

Computes the tritree mesh of LEFT, sparse DP disparities at its vertices, the dense
disparity map and the 2.5D mesh. LEFT/RIGHT: rectified 8-bit PNG/PGM/PPM (gray or RGB).

Outputs:
  --disp OUT.pfm|OUT.png    dense disparity: PFM float (Middlebury, +inf = invalid) or
                            16-bit PNG holding disparity*16 (0 = invalid)
  --disp-format q4|kitti    how a --disp PNG encodes d: q4 (default, value = 16 d) or
                            kitti (value = 256 d, the KITTI benchmark's PNGs)
  --disp-color OUT.png      colour-mapped disparity for viewing
  --mesh OUT.ply            2.5D mesh (binary PLY; --mesh-ascii for ASCII); vertices in
                            (x, y, disparity) or metric 3D with --camera
  --camera F,B,CX,CY[,DOFFS]  focal length (px), baseline, principal point, Middlebury doffs
  --calib FILE              the camera from a calibration file: Middlebury calib.txt, KITTI
                            (P2/P3 or P0/P1) or OpenCV YAML/XML (P1+P2 or Q); sets the metric
                            mesh, --depth, --points and the ROS fields of --stats (metres)
  --calib-format F          auto (default: from the contents), middlebury, kitti, opencv
  --calib-unit m|cm|mm      unit of an OpenCV file's translations (default m)
  --depth OUT.pfm|OUT.png   metric depth: PFM metres (+inf = invalid) or 16-bit PNG
                            millimetres (0 = invalid); needs --calib or --camera
  --points OUT.ply          the dense map as a coloured point cloud in metres
  --samples OUT.csv         the samples (mesh vertices): x,y,disparity (for eval --samples)
  --stats OUT.json          sizes, sample fraction, forced splits, per-stage milliseconds
  --reference               run the float reference instead of the integer pipeline
)";
}  // namespace

int cmd_match(int argc, char** argv) {
  std::set<std::string> values = {"disp",   "disp-color", "mesh",       "camera", "calib",
                                  "calib-format", "disp-format", "calib-unit", "depth", "points", "samples",
                                  "stats"};
  std::set<std::string> flags = {"reference", "mesh-ascii", "help"};
  add_stereo_options(values, flags);
  Args args(argc, argv, values, flags);
  if (args.flag("help")) {
    std::cout << kMatchHelp << stereo_options_help();
    return 0;
  }
  if (args.positional().size() != 2) throw UsageError("match needs LEFT and RIGHT image paths (see --help)");
  const ImageU8 left = read_image_u8(args.positional()[0]);
  const ImageU8 right = read_image_u8(args.positional()[1]);
  if (left.width != right.width || left.height != right.height)
    throw Error(ErrorCode::kSizeMismatch, "left is " + std::to_string(left.width) + "x" +
                                              std::to_string(left.height) + " but right is " +
                                              std::to_string(right.width) + "x" +
                                              std::to_string(right.height));
  const PipelineConfig config = stereo_config_from_args(args, left.width, left.height);

  MatchRun run;
  run.config = config;
  run.camera = camera_from_args(args, left.width, left.height, &run.camera_source);
  if (args.flag("reference")) {
    const auto t0 = std::chrono::steady_clock::now();
    run.output = run_reference(left, right, config.params);
    run.timings.total_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                               std::chrono::steady_clock::now() - t0).count();
    run.implementation = "reference";
  } else {
    Pipeline pipeline;
    pipeline.configure(config);
    run.output = pipeline.process(left.view(), right.view());
    run.timings = pipeline.last_timings();
    run.implementation = std::string("integer/") + to_string(pipeline.active_kernels());
    run.threads = pipeline.worker_count();
  }
  write_match_outputs(args, left, run);
  print_match_summary(std::cout, run);
  return 0;
}

}  // namespace tristereo::cli
