// tristereo match LEFT RIGHT --ndisp D [...]: one pair -> disparity, mesh, stats.
#include <chrono>
#include <cstdio>
#include <fstream>
#include <future>
#include <iostream>

#include "apps/cli_args.hpp"
#include "apps/commands.hpp"
#include "apps/stereo_options.hpp"
#include "apps/match_outputs.hpp"
#include "apps/match_sequence.hpp"
#include "apps/match_warnings.hpp"
#include "apps/output_paths.hpp"
#include "apps/rig_options.hpp"
#include "apps/stereo_pair.hpp"
#include "tristereo/gray.hpp"
#include "platform/thread_pool.hpp"
#include "tristereo/io.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/reference.hpp"
#include "tristereo/status.hpp"

namespace tristereo::cli {

namespace {
const char* kMatchHelp = R"(usage: tristereo match LEFT RIGHT --ndisp D [options]
       tristereo match --folder DIR | --list FILE --ndisp D [options]   (a sequence, below)

Computes the tritree mesh of LEFT, disparities at its vertices (path costs summed on the
mesh by default; --optimizer dp: the paper's row DP), the dense disparity map and the
2.5D mesh. LEFT/RIGHT: rectified 8-bit PNG/PGM/PPM (gray or RGB).

Outputs (each checked before computing: the format follows the extension, other
extensions are refused, no output may name an input or another output; all or nothing:
each is written to a temporary file in its folder, and they are renamed into place
together once every one is complete):
  --disp OUT.pfm|OUT.png    dense disparity: PFM float (Middlebury, +inf = invalid) or
                            16-bit PNG holding disparity*16 (0 = invalid)
  --disp-format q4|kitti    how a --disp PNG encodes d: q4 (default, value = 16 d) or
                            kitti (value = 256 d, the KITTI benchmark's PNGs)
  --disp-color OUT.png      colour-mapped disparity for viewing
  --mesh OUT.ply            2.5D mesh (binary PLY; --mesh-ascii for ASCII); vertices in
                            (x, y, disparity) or metric 3D with --camera
  --camera F,B,CX,CY[,DOFFS]  focal length (px), baseline (metres, or with its unit: 0.12m,
                            12cm, 120mm; a bare value over 10 is refused as a likely
                            unit slip), principal point, Middlebury doffs (px), within
                            the bounds of docs/calibration.md
  --calib FILE              the camera from a calibration file: Middlebury calib.txt, KITTI
                            (P2/P3 or P0/P1) or OpenCV YAML/XML (P1+P2 or Q); sets the metric
                            mesh, --depth, --points and the ROS fields of --stats (metres)
  --calib-format F          auto (default: from the contents), middlebury, kitti, opencv
  --calib-unit m|cm|mm      unit of an OpenCV file's translations (default m)
  --depth OUT.pfm|OUT.png   metric depth: PFM metres (+inf = invalid) or 16-bit PNG
                            millimetres (0 = invalid); needs --calib or --camera
  --points OUT.ply          the dense map as a coloured point cloud in metres
  --min-disparity PX        the metric outputs (--depth, --points, metric --mesh) keep
                            disparities with d + doffs >= PX (default 2: beyond it half a
                            pixel of disparity error is over a quarter of the depth);
                            0 keeps every d + doffs > 0
  --min-depth M, --max-depth M  the metric outputs keep depths in [M, M'] metres (default:
                            no depth limit)
  --points-include-filled   --points and --mesh keep only measured pixels and vertices
                            (those that passed the uniqueness and left-right tests) unless
                            this is given; filled ones are a neighbour's guess
  --valid OUT.png           8-bit state per pixel: 0 invalid, 1 filled (a neighbour's
                            disparity), 2 measured (docs/model.md section 7)
  --confidence OUT.png      8-bit confidence per pixel: 0 invalid, 1..127 filled (fewer
                            the farther from a measured sample), 128..255 measured (more
                            the clearer the best match); --min-confidence C turns every
                            pixel and sample below C invalid in all outputs
  --samples OUT.csv         the samples (mesh vertices): x,y,disparity (for eval --samples)
  --stats OUT.json          sizes, sample fraction, forced splits, per-stage milliseconds,
                            and the run's own (run_ms: reading both inputs, configure,
                            the frame, waiting for the swapped-pair check)
  --reference               run the float reference instead of the integer pipeline

Cost: a frame takes time in proportion to D times (pixels + samples x window area +
samples x path directions), every pixel a sample with --dense, twice that with
--lr-source mirror: about 0.1 ns per term with AVX2 kernels and 1 ns with scalar ones on
one x86 core. The defaults at 640x480, D = 128 take about 65 ms; a dense frame with a
31x31 window and D = 256 takes seconds (docs/reliability.md).

Warnings (stderr, exit 0): LEFT and RIGHT probably swapped, a disparity range with no
match inside the image, more --threads than CPUs, a gray image with an RGB one (matched
in gray), mesh faces left out (vertices without a valid or finite depth).
)";

using Clock = std::chrono::steady_clock;
double ms_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}
}  // namespace

int cmd_match(int argc, char** argv) {
  const Clock::time_point t_start = Clock::now();
  std::set<std::string> values = {"disp",   "disp-color", "mesh",       "camera", "calib",
                                  "calib-format", "disp-format", "calib-unit", "depth", "points", "samples",
                                  "stats", "min-disparity", "min-depth", "max-depth", "valid", "confidence"};
  std::set<std::string> flags = {"reference", "mesh-ascii", "points-include-filled", "help"};
  add_stereo_options(values, flags);
  add_rig_options(values);
  add_sequence_options(values, flags);
  Args args(argc, argv, values, flags);
  if (args.flag("help")) {
    std::cout << kMatchHelp << "\n" << sequence_help() << "\n" << rig_options_help() << "\n"
              << stereo_options_help() << exit_codes_help()
              << "  A sequence (--folder, --list) exits 1 when any frame failed, after the others.\n";
    return 0;
  }
  // Options that act only beside another (cli_args.hpp, OptionNeed).
  static const std::vector<OptionNeed> kNeeds = {
      {"mesh-ascii", {"mesh", "points"}, nullptr, "it writes their PLY files as ASCII"},
      {"calib-format", {"calib"}, nullptr, "it says how to read the calibration file"},
      {"calib-unit", {"calib"}, nullptr, "it gives the unit of an OpenCV calibration file's translations"},
      {"min-disparity", {"depth", "points", "mesh"}, nullptr, "it limits the metric outputs"},
      {"min-depth", {"depth", "points", "mesh"}, nullptr, "it limits the metric outputs"},
      {"max-depth", {"depth", "points", "mesh"}, nullptr, "it limits the metric outputs"},
      {"min-disparity", {"calib", "camera", "rig"}, nullptr, "it limits the metric outputs, which need a camera"},
      {"min-depth", {"calib", "camera", "rig"}, nullptr, "it limits the metric outputs, which need a camera"},
      {"max-depth", {"calib", "camera", "rig"}, nullptr, "it limits the metric outputs, which need a camera"},
      {"rig-right", {"rig"}, nullptr, "it is the right camera's file of a --rig pair"},
      {"points-include-filled", {"points", "mesh"}, nullptr, "it keeps filled pixels and vertices in their PLY files"},
      {"left-pattern", {"folder"}, nullptr, "it names the left frames in that folder"},
      {"right-pattern", {"folder"}, nullptr, "it names the right frames in that folder"},
      {"quiet", {"folder", "list"}, nullptr, "it silences a sequence's summary and progress line"},
  };
  check_option_needs(args, kNeeds);
  if (args.has("folder") || args.has("list")) return match_sequence(args);
  // A rig brings its own rectified camera: a second one would contradict it.
  for (const char* other : {"calib", "camera"})
    if (args.has("rig") && args.has(other))
      throw UsageError(std::string("--rig and --") + other +
                       " both give the camera: --rig's rectified camera is the one of the rectified frames");
  const auto& pos = args.positional();
  check_two_paths("match", pos);
  // Every option is checked before any file is read: a usage error is
  // reported as one (exit 2) even when an input is missing too.
  (void)stereo_config_from_args(args, 2, 2);
  (void)depth_limits_from_args(args);
  const std::string& left_path = pos[0];
  const std::string& right_path = pos[1];
  check_output_paths(args, match_output_options(),
                     {{"LEFT", left_path}, {"RIGHT", right_path}, {"--calib", args.get("calib", "")},
                      {"--rig", args.get("rig", "")}, {"--rig-right", args.get("rig-right", "")}});
  // The two decodes run side by side: PNG decoding is a seventh of a one-shot
  // run's CPU (docs/performance.md, "One-shot match"). A bad LEFT is still the
  // error reported: its exception leaves before RIGHT's result is looked at.
  std::future<ImageU8> right_decoded =
      std::async(std::launch::async, [&right_path] { return read_image_u8(right_path); });
  ImageU8 left = read_image_u8(left_path);
  ImageU8 right = right_decoded.get();
  check_stereo_pair(left_path, left, right_path, right);
  PipelineConfig config = stereo_config_from_args(args, left.width, left.height);
  // Raw frames: the rig's maps go into the pipeline (its rectification
  // stage); the outputs' colours and the reference use the rectified left.
  LoadedRig rig;
  ImageU8 rectified_left, rectified_right;
  if (args.has("rig")) {
    rig = load_rig(args, left.width, left.height);
    config.rectify = rig.maps;
    rectified_left = reference_rectify(rig.rig, rig.rect, 0, left.channels == 1 ? left : to_gray(left));
    if (args.flag("reference"))
      rectified_right = reference_rectify(rig.rig, rig.rect, 1, right.channels == 1 ? right : to_gray(right));
  }
  const StereoParams& p = config.params;
  check_disp_output(args, p);

  MatchRun run;
  Clock::time_point t_mark = Clock::now();
  run.phases.read_inputs_ms = ms_between(t_start, t_mark);
  run.config = config;
  run.camera = camera_from_args(args, left.width, left.height, &run.camera_source);
  run.depth_limits = depth_limits_from_args(args);
  if (args.has("rig")) {
    run.camera = rig.rect.calibration().camera();
    run.camera_source = args.get("rig", "");
  }
  // The swapped-pair check reads the images only: it runs beside the frame
  // (a one-shot match's wall time, docs/performance.md), its warning printed
  // once the frame is done.
  std::future<std::string> swapped = std::async(std::launch::async, [&left, &right, &p] {
    const ImageU8 lg = left.channels == 1 ? ImageU8() : to_gray(left);
    const ImageU8 rg = right.channels == 1 ? ImageU8() : to_gray(right);
    return swapped_warning(left.channels == 1 ? left.view() : lg.view(),
                           right.channels == 1 ? right.view() : rg.view(), p.d_min, p.num_disp);
  });
  for (const std::string& w : {range_outside_image_warning(left.width, p.d_min, p.num_disp),
                               run.camera ? no_depth_warning(*run.camera,
                                                             run.camera_source == "--camera"
                                                                 ? run.camera_source
                                                                 : (args.has("rig") ? "--rig " : "--calib ") +
                                                                       run.camera_source,
                                                             p.d_min, p.num_disp)
                                          : std::string(),
                               threads_warning(config.threads,
                                               static_cast<int>(config.cpus.empty()
                                                                    ? ThreadPool::available_cpus().size()
                                                                    : config.cpus.size()),
                                               !config.cpus.empty())})
    if (!w.empty()) std::cerr << w << "\n";
  Pipeline pipeline;  // lives until the outputs are written: its result is not copied
  if (args.flag("reference")) {
    const auto t0 = Clock::now();
    run.output = args.has("rig") ? run_reference(rectified_left, rectified_right, config.params)
                                 : run_reference(left, right, config.params);
    run.timings.total_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t0).count();
    run.implementation = "reference";
    run.phases.configure_ms = 0;
    run.phases.frame_ms = ms_between(t0, Clock::now());
  } else {
    t_mark = Clock::now();
    pipeline.configure(config);
    const Clock::time_point t_configured = Clock::now();
    run.phases.configure_ms = ms_between(t_mark, t_configured);
    run.result = &pipeline.process(left.view(), right.view());
    run.phases.frame_ms = ms_between(t_configured, Clock::now());
    run.timings = pipeline.last_timings();
    run.implementation = std::string("integer/") + to_string(pipeline.active_kernels());
    run.threads = pipeline.worker_count();
  }
  t_mark = Clock::now();
  const std::string swapped_text = swapped.get();
  run.phases.checks_ms = ms_between(t_mark, Clock::now());
  if (!swapped_text.empty()) std::cerr << swapped_text << "\n";
  write_match_outputs(args, args.has("rig") ? rectified_left : left, run);
  print_match_summary(std::cout, run);
  return 0;
}

}  // namespace tristereo::cli
