// tristereo verify LEFT RIGHT --ndisp D [...]: reference vs every kernel set and thread count.
#include <iostream>

#include "apps/cli_args.hpp"
#include "apps/rig_options.hpp"
#include "apps/commands.hpp"
#include "apps/stereo_options.hpp"
#include "apps/stereo_pair.hpp"
#include "tristereo/io.hpp"
#include "tristereo/status.hpp"
#include "tristereo/verify.hpp"

namespace tristereo::cli {

int cmd_verify(int argc, char** argv) {
  std::set<std::string> values = {"thread-counts"};
  std::set<std::string> flags = {"help"};
  add_stereo_options(values, flags);
  add_rig_options(values);
  Args args(argc, argv, values, flags);
  if (args.flag("help")) {
    std::cout << "usage: tristereo verify LEFT RIGHT --ndisp D [options] [--thread-counts 1,2,3]\n\n"
                 "Runs the float reference and the integer pipeline with every kernel set this CPU\n"
                 "can run (and 1 and N threads), compares mesh, sample disparities and dense map.\n"
                 "Prints 'bit-exact' and exits 0 when all are identical; otherwise prints the first\n"
                 "difference and exits 1. With --rig, LEFT and RIGHT are raw frames: the reference\n"
                 "rectifies them by its float definition, each pipeline by its fixed-point stage.\n\n"
              << stereo_options_help() << "\n" << rig_options_help() << "\n" << exit_codes_help();
    return 0;
  }
  check_two_paths("verify", args.positional());
  // Every option is checked before any file is read: a usage error is
  // reported as one (exit 2) even when an input is missing too.
  (void)stereo_config_from_args(args, 2, 2);
  ImageU8 left = read_image_u8(args.positional()[0]);
  ImageU8 right = read_image_u8(args.positional()[1]);
  check_stereo_pair(args.positional()[0], left, args.positional()[1], right);
  if (args.has("rig-right") && !args.has("rig"))
    throw UsageError("--rig-right has no effect without --rig (it is the right camera's file of a --rig pair)");
  LoadedRig rig;
  if (args.has("rig")) rig = load_rig(args, left.width, left.height);
  const int width = args.has("rig") ? rig.maps->left.width : left.width;
  const int height = args.has("rig") ? rig.maps->left.height : left.height;
  const PipelineConfig config = stereo_config_from_args(args, width, height);
  std::vector<int> thread_counts;
  if (args.has("thread-counts")) {
    std::string s = args.get("thread-counts", "");
    std::size_t pos = 0;
    while (pos <= s.size()) {
      const std::size_t comma = s.find(',', pos);
      const std::string item = s.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
      const int t = parse_int("--thread-counts", item);
      if (t < 1 || t > 256) throw UsageError("--thread-counts: each count must be 1..256");
      thread_counts.push_back(t);
      if (comma == std::string::npos) break;
      pos = comma + 1;
    }
  }
  const VerifyReport report = args.has("rig")
                                   ? verify_bit_exact_raw(left, right, rig.rig, rig.rect, config.params, thread_counts)
                                   : verify_bit_exact(left, right, config.params, thread_counts);
  std::cout << "reference digest " << report.reference_digest << "\n";
  for (const VerifyCase& c : report.cases) {
    std::cout << "  " << to_string(c.kernels) << ", " << c.threads << " thread(s): "
              << (c.identical ? "identical" : "DIFFERENT: " + c.first_difference) << "\n";
  }
  std::cout << (report.bit_exact ? "bit-exact" : "NOT bit-exact") << "\n";
  return report.bit_exact ? 0 : 1;
}

}  // namespace tristereo::cli
