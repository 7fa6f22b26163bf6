// tristereo synth OUTDIR [--width --height --ndisp --seed --frame]: a synthetic pair with exact GT.
#include <filesystem>
#include <iostream>

#include "apps/cli_args.hpp"
#include "apps/commands.hpp"
#include "apps/output_set.hpp"
#include "tristereo/io.hpp"
#include "tristereo/status.hpp"
#include "tristereo/synth.hpp"

namespace tristereo::cli {

int cmd_synth(int argc, char** argv) {
  Args args(argc, argv, {"width", "height", "ndisp", "seed", "frame"}, {"help"});
  if (args.flag("help")) {
    std::cout << "usage: tristereo synth OUTDIR [--width 640] [--height 480] [--ndisp 64] [--seed 1] "
                 "[--frame 0]\n\n"
                 "Writes OUTDIR/left.png, right.png (8-bit gray), disp_left.pfm (exact ground truth,\n"
                 "Middlebury PFM) and nonocc.png (255 = visible in both views).\n" << "\n" << exit_codes_help();
    return 0;
  }
  const auto& pos = args.positional();
  if (pos.empty()) throw UsageError("synth needs OUTDIR, the folder to write the pair into; got no path (see --help)");
  if (pos.size() > 1) {
    std::string list;
    for (const std::string& p : pos) list += (list.empty() ? "" : ", ") + p;
    throw UsageError("synth takes one path, OUTDIR; got " + std::to_string(pos.size()) + " (" + list +
                     "): is an option missing its --name? (see --help)");
  }
  SynthParams sp;
  sp.width = args.get_int_in("width", sp.width, 16, 4096);
  sp.height = args.get_int_in("height", sp.height, 16, 4096);
  sp.num_disp = args.get_int_in("ndisp", sp.num_disp, 8, 256);
  const int seed = args.get_int("seed", static_cast<int>(sp.seed));
  if (seed < 0) throw UsageError("--seed must be >= 0");
  sp.seed = static_cast<std::uint32_t>(seed);
  sp.frame = args.get_int_in("frame", 0, 0, 100000);
  const SyntheticScene scene = make_synthetic_scene(sp);
  const std::filesystem::path dir = args.positional()[0];
  OutputFolder folder(dir);
  // The four files all or nothing (output_set.hpp): a failed run leaves no
  // new left image beside an old ground truth.
  OutputSet outputs;
  outputs.add("OUTDIR", (dir / "left.png").string(), [&](const std::string& p) { write_png_u8(p, scene.left.view()); });
  outputs.add("OUTDIR", (dir / "right.png").string(),
              [&](const std::string& p) { write_png_u8(p, scene.right.view()); });
  outputs.add("OUTDIR", (dir / "disp_left.pfm").string(),
              [&](const std::string& p) { write_pfm(p, scene.disp_left.view()); });
  outputs.add("OUTDIR", (dir / "nonocc.png").string(),
              [&](const std::string& p) { write_png_u8(p, scene.nonocc_mask.view()); });
  outputs.commit();
  folder.keep();
  std::cout << "wrote " << dir.string() << "/{left.png,right.png,disp_left.pfm,nonocc.png} ("
            << sp.width << "x" << sp.height << ", ndisp " << sp.num_disp << ")\n";
  return 0;
}

}  // namespace tristereo::cli
