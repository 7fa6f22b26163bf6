#include "apps/stereo_options.hpp"

#include <cmath>

#include "apps/option_errors.hpp"

#include "platform/cpu_features.hpp"

namespace tristereo::cli {

void add_stereo_options(std::set<std::string>& v, std::set<std::string>& f) {
  for (const char* o : {"ndisp", "dmin", "psnr", "max-area", "min-area", "window", "weights", "lambda", "gap",
                        "truncation", "gamma-color", "gamma-proximity", "kernels", "threads", "cpus",
                        "cost", "census", "ad-weight", "optimizer", "paths", "p1", "p2", "p2-edge",
                        "path-gap", "lr-max-diff", "lr-source", "uniqueness", "fill", "mode"})
    v.insert(o);
  for (const char* o : {"dense", "no-subpixel", "no-pin"}) f.insert(o);
}

PipelineConfig stereo_config_from_args(const Args& a, int width, int height) {
  PipelineConfig c;
  c.max_width = width;
  c.max_height = height;
  StereoParams& p = c.params;
  if (!a.has("ndisp")) throw UsageError("--ndisp D is required (number of disparities, 1..256)");
  // The adaptive weights' scales do nothing with box weights.
  static const std::vector<OptionNeed> kNeeds = {
      {"gamma-color", {"weights"}, "adaptive", "it scales the adaptive weights' colour term"},
      {"gamma-proximity", {"weights"}, "adaptive", "it scales the adaptive weights' distance term"},
  };
  check_option_needs(a, kNeeds);
  if (a.has("mode")) {
    const std::string mode = a.get("mode", "");
    if (mode == "paper") p = paper_params();
    else if (mode != "default") throw UsageError("--mode must be default or paper, not '" + mode + "'");
  }
  p.num_disp = a.get_int("ndisp", 64);
  p.d_min = a.get_int("dmin", 0);
  p.dense = a.flag("dense");
  const double psnr = a.get_double("psnr", p.tritree.psnr_deci_db / 10.0);
  if (!(psnr >= kMinPsnrDeciDb / 10.0 && psnr <= kMaxPsnrDeciDb / 10.0))
    throw UsageError("--psnr " + a.get("psnr", "") + " is out of range [" + std::to_string(kMinPsnrDeciDb / 10) +
                     ", " + std::to_string(kMaxPsnrDeciDb / 10) + "] dB");
  p.tritree.psnr_deci_db = static_cast<int>(std::lround(psnr * 10));
  p.tritree.max_area_px2 = a.get_int("max-area", p.tritree.max_area_px2);
  p.tritree.min_area_px2 = a.get_int("min-area", p.tritree.min_area_px2);
  if (!a.has("min-area") && a.has("max-area") && p.tritree.max_area_px2 >= 1 &&
      p.tritree.min_area_px2 > largest_min_area_px2(p.tritree.max_area_px2)) {
    int needed = 1;  // the smallest A_max that allows it: a power of two >= 2 A_min
    while (needed < 2 * p.tritree.min_area_px2) needed *= 2;
    throw UsageError("--max-area " + std::to_string(p.tritree.max_area_px2) +
                     " is too small for the default minimum area of " + std::to_string(p.tritree.min_area_px2) +
                     " px^2 (that needs --max-area >= " + std::to_string(needed) + "); add --min-area 1");
  }
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
  if (a.has("cost")) as_usage_error("--cost", [&] { p.cost.kind = parse_cost_kind(a.get("cost", "")); });
  if (a.has("census")) {
    auto [w, h] = parse_size("--census", a.get("census", ""));
    p.cost.census_w = w;
    p.cost.census_h = h;
  }
  p.cost.ad_weight_q4 = a.get_int("ad-weight", p.cost.ad_weight_q4);
  if (a.has("optimizer"))
    as_usage_error("--optimizer", [&] { p.optimizer = parse_optimizer(a.get("optimizer", "")); });
  p.paths.directions = a.get_int("paths", p.paths.directions);
  p.paths.p1_q4 = a.get_int("p1", p.paths.p1_q4);
  p.paths.p2_q4 = a.get_int("p2", p.paths.p2_q4);
  p.paths.p2_edge_scale = a.get_int("p2-edge", p.paths.p2_edge_scale);
  if (a.has("path-gap"))
    as_usage_error("--path-gap", [&] { p.paths.gap = parse_gap_policy(a.get("path-gap", "")); });
  p.validity.lr_max_diff_q4 = a.get_int("lr-max-diff", p.validity.lr_max_diff_q4);
  if (a.has("lr-source")) {
    as_usage_error("--lr-source", [&] { p.validity.lr_source = parse_lr_source(a.get("lr-source", "")); });
  } else if (p.optimizer == Optimizer::kRowDp) {
    p.validity.lr_source = LrSource::kMirroredPass;  // the row DP keeps no summed costs
  }
  p.validity.uniqueness_pct = a.get_int("uniqueness", p.validity.uniqueness_pct);
  if (a.has("fill")) as_usage_error("--fill", [&] { p.validity.fill = parse_fill_mode(a.get("fill", "")); });
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
  --mode default|paper the starting point of the options below: this project's
                       defaults, or the paper's model (--cost ad --optimizer dp
                       --window 5x5 --truncation 30 --lr-max-diff -1
                       --psnr 40 --min-area 1)
  --ndisp D            number of disparities searched, 1..256 (required)
  --dmin N             smallest disparity (default 0)
  --psnr DB            tritree split threshold, 10..70 dB in 0.1 steps (default 44;
                       paper 40)
  --max-area PX        tritree maximum triangle area, 1..1024 px^2 (default 100)
  --min-area PX        tritree minimum area: only triangles whose halves have at
                       least PX px^2 split, 1..32 with the default --max-area
                       (half the largest power of two <= it; default 2, paper 1)
  --window WxH         support window, odd sides 1..31 (default 3x3; paper 5x5)
  --weights box|adaptive   support weights (default box)
  --gamma-color G      adaptive weights: colour scale (default 10)
  --gamma-proximity G  adaptive weights: distance^2 scale (default 50)
  --truncation T       cost truncation T_c, 1..255 (default 30; 255 = none)
  --lambda L           smoothness weight in Q4 cost units, 0..32000 (default 40)
  --gap inv_sq|inv|const   gap policy tau(g) of the smoothness penalty (default const)
  --cost ad|census|ad_census   matching cost (default census)
  --census WxH         census transform window, odd sides 3..9, W*H <= 65 (default 5x5)
  --ad-weight W        ad_census: AD share in Q4 (16 = equal), 0..64 (default 8)
  --optimizer paths|dp path aggregation on the mesh (default) or the paper's row DP
  --paths 4|8          path directions (default 4)
  --p1 P --p2 P        path penalties in Q4 cost units (defaults 120, 800)
  --p2-edge T          P2 shrinks across intensity edges by T/(T+|dI|); 0 = off
                       (default 30)
  --path-gap inv_sq|inv|const  penalties scaled by tau(edge length) (default const)
  --lr-max-diff Q4     left-right check tolerance in 1/16 px; -1 = no check (default 16)
  --lr-source costs|mirror  the right view's disparities for that check: from the
                       paths' summed costs (default with --optimizer paths), or
                       a second pass on the mirrored pair (default with dp)
  --uniqueness PCT     uniqueness margin in percent; 0 = off (default 10)
  --fill background|none   invalid samples: filled from the background side, or left invalid
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
