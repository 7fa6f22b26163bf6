// tristereo: command-line front end. Each subcommand lives in apps/cmd_<name>.cpp.
#include <cstring>
#include <iostream>
#include <new>
#include <string>

#include "apps/cli_args.hpp"
#include "apps/cmd_profile.hpp"
#include "apps/commands.hpp"
#include "tristereo/status.hpp"
#include "tristereo/version.hpp"

namespace {
const char* kUsage = R"(usage: tristereo <command> [options]     (tristereo <command> --help for details)

Commands:
  demo [OUTDIR]                 built-in default: synthetic scene -> sparse and dense matching,
                                scores vs exact ground truth, reference check, files in OUTDIR
  match LEFT RIGHT --ndisp D    disparity map, 2.5D mesh and stats for one rectified pair
                                (raw frames with --rig FILE: rectified first)
  rectify LEFT RIGHT --rig FILE rectified PNGs of a raw pair (--out-left, --out-right)
  verify LEFT RIGHT --ndisp D   float reference vs every kernel set: prints 'bit-exact'
  synth OUTDIR                  write a synthetic pair with exact ground truth
  eval DISP GT                  bad 0.5/1/2/3 px and KITTI D1 against ground truth
  profile                       per-frame latency distribution (stages, percentiles)
  info                          build and machine: kernel sets, CPUs, GPIO
)";
}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") ||
      !std::strcmp(argv[1], "help")) {
    std::cout << kUsage << "\n" << tristereo::cli::exit_codes_help();
    return argc < 2 ? 2 : 0;
  }
  if (!std::strcmp(argv[1], "--version")) {
    std::cout << "tristereo " << tristereo::kVersionString << "\n";
    return 0;
  }
  const std::string cmd = argv[1];
  using namespace tristereo::cli;
  try {
    int (*fn)(int, char**) = nullptr;
    if (cmd == "match") fn = cmd_match;
    else if (cmd == "verify") fn = cmd_verify;
    else if (cmd == "synth") fn = cmd_synth;
    else if (cmd == "eval") fn = cmd_eval;
    else if (cmd == "info") fn = cmd_info;
    else if (cmd == "rectify") fn = cmd_rectify;
    else if (cmd == "demo") fn = cmd_demo;
    else if (cmd == "profile") fn = cmd_profile;
    if (!fn) {
      std::cerr << "tristereo: unknown command '" << cmd << "'\n\n" << kUsage;
      return 2;
    }
    return fn(argc - 1, argv + 1);
  } catch (const UsageError& e) {
    std::cerr << "tristereo " << cmd << ": " << e.what() << "\n";
    return 2;
  } catch (const tristereo::Error& e) {
    std::cerr << "tristereo " << cmd << ": error (" << tristereo::error_code_name(e.code())
              << "): " << e.what() << "\n";
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "tristereo " << cmd
              << ": error: out of memory (the input or the options need more memory than this "
                 "process may use: smaller images, a smaller --ndisp, or a higher memory limit)\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "tristereo " << cmd << ": " << e.what() << "\n";
    return 1;
  }
}
