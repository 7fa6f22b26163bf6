#include "apps/stereo_options.hpp"

#include <cmath>

#include "apps/option_errors.hpp"

#include "platform/cpu_features.hpp"

namespace tristereo::cli {

void add_stereo_options(std::set<std::string>& v, std::set<std::string>& f) {
  for (const char* o : {"ndisp", "dmin", "psnr", "max-area", "window", "weights", "lambda", "gap",
                        "truncation", "gamma-color", "gamma-proximity", "kernels", "threads", "cpus"})
    v.insert(o);
  for (const char* o : {"dense", "no-subpixel", "no-pin"}) f.insert(o);
}

PipelineConfig stereo_config_from_args(const Args& a, int width, int height) {
  PipelineConfig c;
  c.max_width = width;
  c.max_height = height;
  StereoParams& p = c.params;
  if (!a.has("ndisp")) throw UsageError("--ndisp D is required (number of disparities, 1..256)");
  p.num_disp = a.get_int("ndisp", 64);
  p.d_min = a.get_int("dmin", 0);
  p.dense = a.flag("dense");
  const double psnr = a.get_double("psnr", 40.0);
  if (!(psnr >= kMinPsnrDeciDb / 10.0 && psnr <= kMaxPsnrDeciDb / 10.0))
    throw UsageError("--psnr " + a.get("psnr", "") + " is out of range [" + std::to_string(kMinPsnrDeciDb / 10) +
                     ", " + std::to_string(kMaxPsnrDeciDb / 10) + "] dB");
  p.tritree.psnr_deci_db = static_cast<int>(std::lround(psnr * 10));
  p.tritree.max_area_px2 = a.get_int("max-area", p.tritree.max_area_px2);
  if (a.has("window")) {
    auto [w, h] = parse_size("--window", a.get("window", ""));
    p.cost.window_w = w;
    p.cost.window_h = h;
  }
  if (a.has("weights")) as_usage_error("--weights", [&] { p.cost.weights = parse_weights(a.get("weights", "")); });
  p.cost.truncation = a.get_int("truncation", p.cost.truncation);
  p.cost.asw_gamma_color = a.get_int("gamma-color", p.cost.asw_gamma_color);
  p.cost.asw_gamma_proximity = a.get_int("gamma-proximity", p.cost.asw_gamma_proximity);
  p.dp.lambda_q4 = a.get_int("lambda", p.dp.lambda_q4);
  if (a.has("gap")) as_usage_error("--gap", [&] { p.dp.gap = parse_gap_policy(a.get("gap", "")); });
  p.dp.subpixel = !a.flag("no-subpixel");
  as_usage_error(nullptr, [&] { validate_params(p); });
  as_usage_error("--kernels", [&] { c.kernels = parse_kernel_choice(a.get("kernels", "auto")); });
  c.threads = a.get_int("threads", 0);
  if (c.threads < 0 || c.threads > 256) throw UsageError("--threads must be 0 (one per CPU) .. 256");
  if (a.has("cpus")) as_usage_error("--cpus", [&] { c.cpus = parse_cpu_list(a.get("cpus", "")); });
  c.pin_threads = !a.flag("no-pin");
  return c;
}

const char* stereo_options_help() {
  return R"(Model options (docs/model.md):
  --ndisp D            number of disparities searched, 1..256 (required)
  --dmin N             smallest disparity (default 0)
  --psnr DB            tritree split threshold, 10..70 dB in 0.1 steps (default 40)
  --max-area PX        tritree maximum triangle area, 1..1024 px^2 (default 100)
  --window WxH         support window, odd sides 1..31 (default 5x5)
  --weights box|adaptive   support weights (default box)
  --gamma-color G      adaptive weights: colour scale (default 10)
  --gamma-proximity G  adaptive weights: distance^2 scale (default 50)
  --truncation T       cost truncation T_c, 1..255 (default 30; 255 = none)
  --lambda L           smoothness weight in Q4 cost units, 0..32000 (default 40)
  --gap inv_sq|inv|const   gap policy tau(g) of the smoothness penalty (default const)
  --no-subpixel        integer disparities only
  --dense              every pixel a DP sample (the paper's dense baseline)
Run options:
  --kernels auto|scalar|sse2|avx2|neon   kernel set (default auto; env TRISTEREO_KERNELS)
  --threads N          worker threads, 0 = one per allowed CPU (default 0)
  --cpus LIST          CPUs to pin workers to, e.g. 2,3 or 0-3 (default: allowed set)
  --no-pin             do not pin workers to CPUs
)";
}

}  // namespace tristereo::cli
