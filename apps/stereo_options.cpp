#include "apps/stereo_options.hpp"

#include <string>
#include <vector>

#include "apps/option_errors.hpp"

#include "platform/cpu_features.hpp"
#include "src/model/model_options.hpp"
#include "tristereo/status.hpp"

namespace tristereo::cli {

void add_stereo_options(std::set<std::string>& v, std::set<std::string>& f) {
  for (const ModelOption& o : model_options()) (o.kind == ModelOptionKind::kFlag ? f : v).insert(o.name);
  for (const char* o : {"kernels", "threads", "cpus"}) v.insert(o);
  f.insert("no-pin");
}

PipelineConfig stereo_config_from_args(const Args& a, int width, int height) {
  PipelineConfig c;
  c.max_width = width;
  c.max_height = height;
  if (!a.has("ndisp")) throw UsageError("--ndisp D is required (number of disparities, 1..256)");
  // The adaptive weights' scales do nothing with box weights.
  static const std::vector<OptionNeed> kNeeds = {
      {"gamma-color", {"weights"}, "adaptive", "it scales the adaptive weights' colour term"},
      {"gamma-proximity", {"weights"}, "adaptive", "it scales the adaptive weights' distance term"},
  };
  check_option_needs(a, kNeeds);
  // The model's options through the table the Python module uses too, so
  // both take the same values with the same defaults, checks and messages.
  std::vector<GivenOption> given;
  for (const ModelOption& o : model_options())
    if (a.has(o.name)) given.push_back({&o, o.kind == ModelOptionKind::kFlag ? "" : a.get(o.name, "")});
  try {
    c.params = model_params(given, OptionSpelling::kCommandLine, /*refuse_without_effect=*/true);
  } catch (const Error& e) {
    if (e.code() != ErrorCode::kInvalidArgument) throw;
    throw UsageError(e.what());
  }
  as_usage_error("--kernels", [&] { c.kernels = parse_kernel_choice(a.get("kernels", "auto")); });
  c.threads = a.get_int("threads", 0);
  if (c.threads < 0 || c.threads > 256) throw UsageError("--threads must be 0 (one per CPU) .. 256");
  if (a.has("cpus")) as_usage_error("--cpus", [&] { c.cpus = parse_cpu_list(a.get("cpus", "")); });
  c.pin_threads = !a.flag("no-pin");
  return c;
}

const char* stereo_options_help() {
  // The model's lines come from the option table (src/model/model_options.cpp).
  static const std::string text = "Model options (docs/model.md):\n" + model_options_help() + R"(Run options:
  --kernels auto|scalar|sse2|avx2|neon   kernel set (default auto; env TRISTEREO_KERNELS)
  --threads N          worker threads, 0 = one per allowed CPU (default 0)
  --cpus LIST          CPUs to pin workers to, e.g. 2,3 or 0-3 (default: allowed set)
  --no-pin             do not pin workers to CPUs
)";
  return text.c_str();
}

}  // namespace tristereo::cli
