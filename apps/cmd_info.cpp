// tristereo info: what this build and this machine offer.
#include <iostream>

#include "apps/cli_args.hpp"
#include "apps/commands.hpp"
#include "platform/cpu_features.hpp"
#include "platform/gpio.hpp"
#include "tristereo/kernels.hpp"
#include "tristereo/version.hpp"

namespace tristereo::cli {

int cmd_info(int argc, char** argv) {
  Args args(argc, argv, {}, {"help"});
  if (args.flag("help")) {
    std::cout << "usage: tristereo info\n\nPrints the version, the compiled, available and "
                 "default kernel sets, the CPUs and GPIO support.\n" << "\n" << exit_codes_help();
    return 0;
  }
  if (!args.positional().empty()) throw UsageError("info takes no paths; got '" + args.positional()[0] + "'");
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
  return 0;
}

}  // namespace tristereo::cli
