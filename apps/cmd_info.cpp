// tristereo info: what this build and this machine offer, and the working
// memory a pipeline configured for a given maximum size and D allocates.
#include <cstdio>
#include <iostream>
#include <utility>

#include "apps/cli_args.hpp"
#include "apps/rig_options.hpp"
#include "apps/option_errors.hpp"
#include "apps/commands.hpp"
#include "platform/cpu_features.hpp"
#include "platform/gpio.hpp"
#include "platform/huge_pages.hpp"
#include "tristereo/kernels.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/version.hpp"

namespace tristereo::cli {

int cmd_info(int argc, char** argv) {
  std::set<std::string> values = {"max-size", "ndisp", "threads"};
  add_rig_options(values);
  Args args(argc, argv, values, {"dense", "help"});
  if (args.flag("help")) {
    std::cout << "usage: tristereo info [--max-size WxH] [--ndisp D] [--threads N] [--dense]\n\n"
                 "Prints the version, the compiled, available and default kernel sets, the CPUs,\n"
                 "GPIO support, and the working memory of a pipeline configured for frames up to\n"
                 "WxH (default 640x480) with D disparities (default 64) on N workers (default 0:\n"
                 "one per allowed CPU): the bytes it allocates once, in total and per configured\n"
                 "pixel (docs/performance.md, \"Working memory\"). With --rig FILE [--rig-right\n"
                 "FILE2], for that rig's raw frames (their size, unless --max-size): the\n"
                 "rectification maps are counted too, and printed on their own line.\n"
              << "\n" << exit_codes_help();
    return 0;
  }
  if (!args.positional().empty()) throw UsageError("info takes no paths; got '" + args.positional()[0] + "'");
  PipelineConfig config;
  // Every value is checked here, in the words the user typed (exit 2), not
  // left to configure(), whose errors name its fields and exit 1.
  if (args.has("rig-right") && !args.has("rig")) throw UsageError("--rig-right needs --rig");
  if (args.has("max-size")) {
    const auto [w, h] = parse_size("--max-size", args.get("max-size", ""));
    for (const auto& [side, v] : {std::pair<const char*, int>{"width", w}, {"height", h}})
      if (v < 2 || v > kMaxImageSide)
        throw UsageError("--max-size " + args.get("max-size", "") + ": the " + side + " " + std::to_string(v) +
                         " is out of range [2, " + std::to_string(kMaxImageSide) + "]");
    config.max_width = w;
    config.max_height = h;
  }
  config.params.num_disp = args.get_int("ndisp", 64);
  config.params.dense = args.flag("dense");
  as_usage_error(nullptr, [&] { validate_params(config.params); });  // "--ndisp 0 is out of range ..."
  config.threads = args.get_int("threads", 0);
  if (config.threads < 0 || config.threads > 256) throw UsageError("--threads must be 0 (one per CPU) .. 256");
  config.pin_threads = false;

  std::cout << "tristereo " << kVersionString << "\n";
  std::cout << "cpu: " << cpu_model_name() << "\n";
  std::cout << "kernel sets compiled:";
  for (KernelChoice k : compiled_kernel_sets()) std::cout << ' ' << to_string(k);
  std::cout << "\nkernel sets available on this CPU:";
  for (KernelChoice k : available_kernel_sets()) std::cout << ' ' << to_string(k);
  std::cout << "\nkernel set used by default: " << to_string(resolve_kernel_choice(KernelChoice::kAuto))
            << "\nallowed CPUs:";
  for (int c : allowed_cpus()) std::cout << ' ' << c;
  std::cout << " (online: " << online_cpu_count() << ")\n";
  std::cout << "GPIO frame markers (libgpiod v1): " << (gpio_supported() ? "yes" : "no") << "\n";
  const HugePagePolicy& huge = huge_page_policy();
  std::cout << "huge pages for the large buffers: " << (huge.advise ? "advised" : "off") << " (" << huge.reason
            << ")\n";

  // The real allocation, not an estimate: what configure() sizes is counted
  // by the pipeline itself. No frame is run.
  LoadedRig rig;
  if (args.has("rig")) {
    const StereoRig r = read_rig(args.get("rig", ""), args.get("rig-right", ""));
    if (!args.has("max-size")) {
      config.max_width = r.left.width;
      config.max_height = r.left.height;
    }
    rig = load_rig(args, r.left.width, r.left.height);
    config.rectify = rig.maps;
    std::printf("rectification maps: %zu bytes (%.1f MiB) for %dx%d, %zu border pixels (6 bytes per pixel "
                "and camera: int16 x, y and a uint16 of the two 5-bit fractions)\n",
                rig.maps->memory_bytes(), rig.maps->memory_bytes() / (1024.0 * 1024.0), rig.maps->left.width,
                rig.maps->left.height, rig.maps->left.border.size() + rig.maps->right.border.size());
  }
  Pipeline pipeline;
  pipeline.configure(config);
  const double bytes = static_cast<double>(pipeline.working_memory_bytes());
  const double pixels = static_cast<double>(config.max_width) * config.max_height;
  char line[256];
  std::snprintf(line, sizeof line,
                "working memory: %.0f bytes (%.1f MiB) for %dx%d, D=%d, %s, %d worker(s): "
                "%.1f bytes per configured pixel\n",
                bytes, bytes / (1024.0 * 1024.0), config.max_width, config.max_height,
                config.params.num_disp, config.params.dense ? "dense" : "sparse", pipeline.worker_count(),
                bytes / pixels);
  std::cout << line;
  return 0;
}

}  // namespace tristereo::cli
