// tristereo demo [OUTDIR]: the built-in default job on a generated scene with exact ground truth.
#include <filesystem>
#include <iostream>

#include "apps/cli_args.hpp"
#include "apps/commands.hpp"
#include "apps/output_set.hpp"
#include "apps/match_outputs.hpp"
#include "tristereo/eval.hpp"
#include "tristereo/io.hpp"
#include "tristereo/status.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/synth.hpp"
#include "tristereo/verify.hpp"

namespace tristereo::cli {

namespace {
void print_bad(const char* label, const BadPixelStats& s) {
  std::printf("  %-28s bad>0.5 %6.2f%%   bad>1 %6.2f%%   bad>2 %6.2f%%\n", label, s.bad_0_5, s.bad_1, s.bad_2);
}

Image<float> to_float(const ImageS16& q4) { return disp_q4_to_float(q4.view()); }
}  // namespace

int cmd_demo(int argc, char** argv) {
  Args args(argc, argv, {"width", "height", "ndisp", "seed", "threads"}, {"help"});
  if (args.flag("help")) {
    std::cout << "usage: tristereo demo [OUTDIR (default demo-out)] [--width 640] [--height 480] "
                 "[--ndisp 64] [--seed 1] [--threads 0]\n\n"
                 "Generates a synthetic stereo scene with exact ground truth, matches it sparse (at the\n"
                 "tritree's vertices) and dense (every pixel, the baseline), checks the integer pipeline against the float reference, scores\n"
                 "both against the ground truth and writes the inputs, disparity maps (PFM + colour\n"
                 "PNG), the 2.5D mesh (PLY) and stats (JSON) to OUTDIR.\n" << "\n" << exit_codes_help();
    return 0;
  }
  if (args.positional().size() > 1)
    throw UsageError("demo takes at most one path, OUTDIR; got " + std::to_string(args.positional().size()));
  const std::filesystem::path dir = args.positional().empty() ? "demo-out" : args.positional()[0];
  SynthParams sp;
  sp.width = args.get_int_in("width", 640, 16, 4096);
  sp.height = args.get_int_in("height", 480, 16, 4096);
  sp.num_disp = args.get_int_in("ndisp", 64, 8, 256);
  sp.seed = static_cast<std::uint32_t>(args.get_int_in("seed", 1, 0, 2147483647));
  const int threads = args.get_int_in("threads", 0, 0, 256);
  const SyntheticScene scene = make_synthetic_scene(sp);
  OutputFolder folder(dir.string());
  // Every file of the demo all or nothing (output_set.hpp), written once both
  // runs are done: a failure leaves no mix of this run's files and an older one's.
  OutputSet outputs;
  auto add = [&](const std::string& name, std::function<void(const std::string&)> write) {
    outputs.add("OUTDIR", (dir / name).string(), std::move(write));
  };
  add("left.png", [&](const std::string& p) { write_png_u8(p, scene.left.view()); });
  add("right.png", [&](const std::string& p) { write_png_u8(p, scene.right.view()); });
  add("gt_disp.pfm", [&](const std::string& p) { write_pfm(p, scene.disp_left.view()); });

  std::cout << "synthetic scene " << sp.width << "x" << sp.height << ", D = " << sp.num_disp
            << " -> " << dir.string() << "/\n";
  MatchRun runs[2];  // sparse, dense: kept until the outputs are written
  for (bool dense : {false, true}) {
    MatchRun& run = runs[dense ? 1 : 0];
    run.config.max_width = sp.width;
    run.config.max_height = sp.height;
    run.config.params.num_disp = sp.num_disp;
    run.config.params.dense = dense;
    run.config.threads = threads;
    run.config.pin_threads = false;
    Pipeline pipeline;
    pipeline.configure(run.config);
    run.output = pipeline.process(scene.left.view(), scene.right.view());
    run.timings = pipeline.last_timings();
    run.implementation = std::string("integer/") + to_string(pipeline.active_kernels());
    run.threads = pipeline.worker_count();
    const std::string tag = dense ? "dense" : "sparse";
    add(tag + "_disp.pfm", [&run](const std::string& p) { write_disparity(p, run.output.disp_q4.view()); });
    add(tag + "_disp_color.png", [&run, &sp](const std::string& p) {
      write_disparity_color(p, run.output.disp_q4.view(), 0, sp.num_disp);
    });
    add(tag + "_stats.json", [&run](const std::string& p) { write_stats_json(p, run); });
    if (!dense)
      add("mesh.ply", [&run, &scene](const std::string& p) {
        write_mesh_ply(p, run.output.mesh, run.output.vertex_disp_q4, scene.left.view(), nullptr, true);
      });
    std::cout << "\n" << tag << ": ";
    print_match_summary(std::cout, run);
    const Image<float> disp = to_float(run.output.disp_q4);
    print_bad("dense map, all pixels", evaluate_disparity(disp.view(), scene.disp_left.view(), {}));
    print_bad("dense map, non-occluded", evaluate_disparity(disp.view(), scene.disp_left.view(),
                                                            scene.nonocc_mask.view()));
    print_bad("at the samples, non-occl.", evaluate_at_points(scene.disp_left.view(), run.output.mesh.vertices,
                                                              run.output.vertex_disp_q4,
                                                              scene.nonocc_mask.view()));
  }
  outputs.commit();
  folder.keep();
  const VerifyReport report = verify_bit_exact(scene.left, scene.right, [&] {
    StereoParams p;
    p.num_disp = sp.num_disp;
    return p;
  }());
  std::cout << "\nfloat reference vs integer path (" << report.cases.size()
            << " kernel-set/thread combinations): " << (report.bit_exact ? "bit-exact" : "NOT bit-exact")
            << "\n";
  return report.bit_exact ? 0 : 1;
}

}  // namespace tristereo::cli
