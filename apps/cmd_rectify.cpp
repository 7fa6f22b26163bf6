// tristereo rectify LEFT RIGHT --rig FILE [--rig-right FILE2] --out-left A.png --out-right B.png
#include <iostream>

#include "apps/cli_args.hpp"
#include "apps/commands.hpp"
#include "apps/output_paths.hpp"
#include "apps/output_set.hpp"
#include "apps/rig_options.hpp"
#include "apps/stereo_pair.hpp"
#include "tristereo/gray.hpp"
#include "tristereo/io.hpp"
#include "tristereo/kernels.hpp"
#include "tristereo/status.hpp"

namespace tristereo::cli {

namespace {
const char* kRectifyHelp = R"(usage: tristereo rectify LEFT RIGHT --rig FILE [--rig-right FILE2] --out-left A.png --out-right B.png

Rectifies a raw stereo pair with its rig's calibration and writes both rectified images
as 8-bit gray PNG (colour input is converted with the BT.601 rule first). The maps are
those of `match --rig` (docs/calibration.md): 1/32-pixel source positions, integer
bilinear weights, black beyond the raw image. Prints the rectified camera (f, B, cx, cy).

  --out-left A.png          the rectified left image
  --out-right B.png         the rectified right image
  --kernels SET             auto (default), scalar, sse2, avx2 or neon
)";
}  // namespace

int cmd_rectify(int argc, char** argv) {
  std::set<std::string> values = {"out-left", "out-right", "kernels"};
  add_rig_options(values);
  Args args(argc, argv, values, {"help"});
  if (args.flag("help")) {
    std::cout << kRectifyHelp << "\n" << rig_options_help() << "\n" << exit_codes_help();
    return 0;
  }
  const auto& pos = args.positional();
  check_two_paths("rectify", pos);
  if (!args.has("rig")) throw UsageError("rectify needs --rig FILE, the calibration of the raw pair");
  if (args.has("rig-right") && !args.has("rig")) throw UsageError("--rig-right needs --rig");
  for (const char* out : {"out-left", "out-right"})
    if (!args.has(out)) throw UsageError(std::string("rectify needs --") + out + " OUT.png");
  KernelChoice kernels = KernelChoice::kAuto;
  try {
    kernels = parse_kernel_choice(args.get("kernels", "auto"));
  } catch (const Error& e) {
    throw UsageError(std::string("--kernels: ") + e.what());
  }
  check_output_paths(args, {{"out-left", {".png"}}, {"out-right", {".png"}}},
                     {{"LEFT", pos[0]}, {"RIGHT", pos[1]}, {"--rig", args.get("rig", "")},
                      {"--rig-right", args.get("rig-right", "")}});
  ImageU8 left = read_image_u8(pos[0]);
  ImageU8 right = read_image_u8(pos[1]);
  check_stereo_pair(pos[0], left, pos[1], right);
  const LoadedRig rig = load_rig(args, left.width, left.height);
  const ImageU8 lg = left.channels == 1 ? left : to_gray(left);
  const ImageU8 rg = right.channels == 1 ? right : to_gray(right);
  ImageU8 out_l(rig.maps->left.width, rig.maps->left.height, 1), out_r(rig.maps->right.width, rig.maps->right.height, 1);
  remap_image(rig.maps->left, lg.view(), out_l.view(), kernels);
  remap_image(rig.maps->right, rg.view(), out_r.view(), kernels);
  OutputSet outputs;
  outputs.add("--out-left", args.get("out-left", ""), [&](const std::string& p) { write_png_u8(p, out_l.view()); });
  outputs.add("--out-right", args.get("out-right", ""), [&](const std::string& p) { write_png_u8(p, out_r.view()); });
  outputs.commit();
  const StereoCalibration cal = rig.rect.calibration();
  std::cout << "rig: " << to_string(rig.rig.format) << ", " << to_string(rig.rig.left.model) << " lenses, "
            << (rig.rect.from_file ? "the file's rectification" : "rectification computed (alpha 0)") << "\n"
            << "rectified: " << out_l.width << "x" << out_l.height << ", f " << cal.focal_px << " px, baseline "
            << cal.baseline_m << ", cx " << cal.cx_px << ", cy " << cal.cy_px << ", doffs " << cal.doffs_px << "\n"
            << "maps: " << rig.maps->memory_bytes() << " bytes (" << rig.maps->left.border.size() + rig.maps->right.border.size()
            << " border pixels)\n";
  return 0;
}

}  // namespace tristereo::cli
