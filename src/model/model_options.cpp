// The model's options, one table for the command line and the Python module
// (model_options.hpp says why).
#include "src/model/model_options.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <tuple>
#include <utility>

#include "tristereo/status.hpp"

namespace tristereo {

namespace {

[[noreturn]] void bad(const std::string& what) { throw Error(ErrorCode::kInvalidArgument, what); }

// The parsers say what was expected in the words the command line always used.
int parse_int_text(const std::string& shown, const std::string& text) {
  errno = 0;
  char* end = nullptr;
  const long long v = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || std::isspace(static_cast<unsigned char>(text[0])))
    bad(shown + ": '" + text + "' is not an integer");
  // INT_MIN is refused too, so that no caller has to care about negating it.
  if (errno == ERANGE || v < -2147483647LL || v > 2147483647LL)
    bad(shown + " " + text + " is out of range (far beyond what any option accepts)");
  return static_cast<int>(v);
}

double parse_decimal_text(const std::string& shown, const std::string& text) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !(v == v) || std::isspace(static_cast<unsigned char>(text[0])))
    bad(shown + ": '" + text + "' is not a number");
  if (errno == ERANGE && (v > 1 || v < -1)) bad(shown + " " + text + " is out of range");
  if (!std::isfinite(v)) bad(shown + ": '" + text + "' is not a finite number");
  return v;
}

std::pair<int, int> parse_size_text(const std::string& shown, const std::string& text) {
  const auto x = text.find('x');
  if (x != std::string::npos && (x == 0 || x + 1 == text.size() || text.find('x', x + 1) != std::string::npos))
    bad(shown + ": '" + text + "' is not a size (W or WxH, e.g. 5x5)");
  if (x == std::string::npos) {
    // A lone number is a square; anything else is not a size at all.
    const bool digits = !text.empty() && text.find_first_not_of("+-0123456789") == std::string::npos;
    if (!digits) bad(shown + ": '" + text + "' is not a size (W or WxH, e.g. 5x5)");
    const int s = parse_int_text(shown, text);
    return {s, s};
  }
  return {parse_int_text(shown, text.substr(0, x)), parse_int_text(shown, text.substr(x + 1))};
}

// The library's own parse_* messages ("unknown gap policy 'sq' (expected ...)")
// prefixed by the option.
template <typename F>
auto parse_choice(const std::string& shown, F parse) -> decltype(parse()) {
  try {
    return parse();
  } catch (const Error& e) {
    bad(shown + ": " + e.what());
  }
}

std::string size_text(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

std::string tenths_text(int tenths) {
  std::string s = std::to_string(tenths / 10);
  if (tenths % 10 != 0) s += "." + std::to_string(std::abs(tenths % 10));
  return s;
}

using K = ModelOptionKind;
using P = StereoParams;
using S = const std::string&;

// One row per option. `mode` and `ndisp` are handled by model_params() (the
// one sets the starting point, the other is required), so their setters only
// check the value.
const std::vector<ModelOption> kOptions = {
    {"mode", "mode", K::kChoice, "default|paper", 0, 0, false, "default|paper",
     "the starting point of the options below: this project's defaults, or the paper's model (--cost ad "
     "--optimizer dp --window 5x5 --truncation 30 --lr-max-diff -1 --uniqueness 0 --psnr 40 --min-area 1)",
     nullptr, nullptr, nullptr, [](const P&) { return std::string("default"); },
     [](P&, S t, S shown) {
       if (t != "default" && t != "paper") bad(shown + " must be default or paper, not '" + t + "'");
     }},
    {"ndisp", "ndisp", K::kInt, "D", 1, kMaxNumDisp, false, nullptr, "number of disparities searched", nullptr,
     nullptr, "num_disp", [](const P& p) { return std::to_string(p.num_disp); },
     [](P& p, S t, S shown) { p.num_disp = parse_int_text(shown, t); }},
    {"dmin", "dmin", K::kInt, "N", -(kMaxDispSpan - 1), kMaxDispSpan - 1, true, nullptr,
     "smallest disparity (|dmin| + ndisp <= 2048)", nullptr, nullptr, "d_min",
     [](const P& p) { return std::to_string(p.d_min); }, [](P& p, S t, S shown) { p.d_min = parse_int_text(shown, t); }},
    {"psnr", "psnr", K::kDecimal, "DB", kMinPsnrDeciDb, kMaxPsnrDeciDb, false, nullptr,
     "tritree split threshold in dB, in 0.1 steps", nullptr, nullptr, "tritree.psnr_deci_db=(in 0.1 dB)",
     [](const P& p) { return tenths_text(p.tritree.psnr_deci_db); },
     [](P& p, S t, S shown) {
       const double v = parse_decimal_text(shown, t);
       // Checked here, before rounding to tenths, so the message shows the value given.
       if (!(v >= kMinPsnrDeciDb / 10.0 && v <= kMaxPsnrDeciDb / 10.0))
         bad(shown + " " + t + " is out of range [" + tenths_text(kMinPsnrDeciDb) + ", " +
             tenths_text(kMaxPsnrDeciDb) + "] dB");
       p.tritree.psnr_deci_db = static_cast<int>(std::lround(v * 10));
     }},
    {"max-area", "max_area", K::kInt, "PX", 1, kMaxAreaLimitPx2, false, nullptr,
     "tritree maximum triangle area in px^2", nullptr, nullptr, "tritree.max_area_px2",
     [](const P& p) { return std::to_string(p.tritree.max_area_px2); },
     [](P& p, S t, S shown) { p.tritree.max_area_px2 = parse_int_text(shown, t); }},
    {"min-area", "min_area", K::kInt, "PX", 1, largest_min_area_px2(kMaxAreaLimitPx2), true, nullptr,
     "tritree minimum area: only triangles whose halves have at least PX px^2 split; at most half the "
     "largest power of two <= max-area (32 with its default)",
     nullptr, nullptr, "tritree.min_area_px2", [](const P& p) { return std::to_string(p.tritree.min_area_px2); },
     [](P& p, S t, S shown) { p.tritree.min_area_px2 = parse_int_text(shown, t); }},
    {"window", "window", K::kSize, "WxH", 1, kMaxWindowSide, false, nullptr, "support window, odd sides",
     nullptr, nullptr, "cost.window_w=width;cost.window_h=height",
     [](const P& p) { return size_text(p.cost.window_w, p.cost.window_h); },
     [](P& p, S t, S shown) { std::tie(p.cost.window_w, p.cost.window_h) = parse_size_text(shown, t); }},
    {"weights", "weights", K::kChoice, "box|adaptive", 0, 0, false, "box|adaptive",
     "support weights (adaptive: with --cost ad)", nullptr, nullptr, "cost.weights",
     [](const P& p) { return std::string(to_string(p.cost.weights)); },
     [](P& p, S t, S shown) { p.cost.weights = parse_choice(shown, [&] { return parse_weights(t); }); }},
    {"gamma-color", "gamma_color", K::kInt, "G", 1, 1000, false, nullptr, "adaptive weights: colour scale",
     "weights", "adaptive", "cost.asw_gamma_color", [](const P& p) { return std::to_string(p.cost.asw_gamma_color); },
     [](P& p, S t, S shown) { p.cost.asw_gamma_color = parse_int_text(shown, t); }},
    {"gamma-proximity", "gamma_proximity", K::kInt, "G", 1, 100000, false, nullptr,
     "adaptive weights: distance^2 scale", "weights", "adaptive", "cost.asw_gamma_proximity",
     [](const P& p) { return std::to_string(p.cost.asw_gamma_proximity); },
     [](P& p, S t, S shown) { p.cost.asw_gamma_proximity = parse_int_text(shown, t); }},
    {"truncation", "truncation", K::kInt, "T", 1, 255, false, nullptr, "AD cost truncation T_c (255 = none)",
     "cost", "ad|ad_census", "cost.truncation", [](const P& p) { return std::to_string(p.cost.truncation); },
     [](P& p, S t, S shown) { p.cost.truncation = parse_int_text(shown, t); }},
    {"lambda", "lambda_q4", K::kInt, "L", 0, kMaxLambdaQ4, false, nullptr,
     "row DP smoothness weight in Q4 cost units", "optimizer", "dp", "dp.lambda_q4",
     [](const P& p) { return std::to_string(p.dp.lambda_q4); },
     [](P& p, S t, S shown) { p.dp.lambda_q4 = parse_int_text(shown, t); }},
    {"gap", "gap", K::kChoice, "inv_sq|inv|const", 0, 0, false, "inv_sq|inv|const",
     "row DP: gap policy tau(g) of the smoothness penalty", "optimizer", "dp", nullptr,
     [](const P& p) { return std::string(to_string(p.dp.gap)); },
     [](P& p, S t, S shown) { p.dp.gap = parse_choice(shown, [&] { return parse_gap_policy(t); }); }},
    {"cost", "cost", K::kChoice, "ad|census|ad_census", 0, 0, false, "ad|census|ad_census", "matching cost",
     nullptr, nullptr, nullptr, [](const P& p) { return std::string(to_string(p.cost.kind)); },
     [](P& p, S t, S shown) { p.cost.kind = parse_choice(shown, [&] { return parse_cost_kind(t); }); }},
    {"census", "census", K::kSize, "WxH", 3, 9, false, nullptr, "census transform window, W*H <= 65, odd sides",
     "cost", "census|ad_census", "cost.census_w=width;cost.census_h=height",
     [](const P& p) { return size_text(p.cost.census_w, p.cost.census_h); },
     [](P& p, S t, S shown) { std::tie(p.cost.census_w, p.cost.census_h) = parse_size_text(shown, t); }},
    {"ad-weight", "ad_weight", K::kInt, "W", 0, kMaxAdWeightQ4, false, nullptr,
     "ad_census: AD share in Q4 (16 = equal)", "cost", "ad_census", "cost.ad_weight_q4",
     [](const P& p) { return std::to_string(p.cost.ad_weight_q4); },
     [](P& p, S t, S shown) { p.cost.ad_weight_q4 = parse_int_text(shown, t); }},
    {"optimizer", "optimizer", K::kChoice, "paths|dp", 0, 0, false, "paths|dp",
     "path aggregation on the mesh, or the paper's row DP", nullptr, nullptr, nullptr,
     [](const P& p) { return std::string(to_string(p.optimizer)); },
     [](P& p, S t, S shown) { p.optimizer = parse_choice(shown, [&] { return parse_optimizer(t); }); }},
    {"paths", "paths", K::kChoice, "4|8", 4, 8, false, "4|8", "path directions", "optimizer", "paths",
     "paths.directions", [](const P& p) { return std::to_string(p.paths.directions); },
     [](P& p, S t, S shown) {
       if (t != "4" && t != "8") bad(shown + " must be 4 or 8, not '" + t + "'");
       p.paths.directions = parse_int_text(shown, t);
     }},
    {"p1", "p1", K::kInt, "P", 0, kMaxPathPenaltyQ4, false, nullptr,
     "path penalty of a one-step disparity change, Q4 cost units", "optimizer", "paths", "paths.p1_q4",
     [](const P& p) { return std::to_string(p.paths.p1_q4); },
     [](P& p, S t, S shown) { p.paths.p1_q4 = parse_int_text(shown, t); }},
    {"p2", "p2", K::kInt, "P", 0, kMaxPathPenaltyQ4, true, nullptr,
     "path penalty of a larger jump, Q4 cost units, >= p1", "optimizer", "paths", "paths.p2_q4",
     [](const P& p) { return std::to_string(p.paths.p2_q4); },
     [](P& p, S t, S shown) { p.paths.p2_q4 = parse_int_text(shown, t); }},
    {"p2-edge", "p2_edge", K::kInt, "T", 0, 255, false, nullptr,
     "P2 shrinks across intensity edges by T/(T+|dI|); 0 = off", "optimizer", "paths", "paths.p2_edge_scale",
     [](const P& p) { return std::to_string(p.paths.p2_edge_scale); },
     [](P& p, S t, S shown) { p.paths.p2_edge_scale = parse_int_text(shown, t); }},
    {"path-gap", "path_gap", K::kChoice, "inv_sq|inv|const", 0, 0, false, "inv_sq|inv|const",
     "path penalties scaled by tau(edge length)", "optimizer", "paths", nullptr,
     [](const P& p) { return std::string(to_string(p.paths.gap)); },
     [](P& p, S t, S shown) { p.paths.gap = parse_choice(shown, [&] { return parse_gap_policy(t); }); }},
    {"lr-max-diff", "lr_max_diff", K::kInt, "Q4", -1, 16 * kMaxNumDisp, false, nullptr,
     "left-right check tolerance in 1/16 px; -1 = no check", nullptr, nullptr, "validity.lr_max_diff_q4",
     [](const P& p) { return std::to_string(p.validity.lr_max_diff_q4); },
     [](P& p, S t, S shown) { p.validity.lr_max_diff_q4 = parse_int_text(shown, t); }},
    {"lr-source", "lr_source", K::kChoice, "costs|mirror", 0, 0, false, "costs|mirror",
     "the right view's disparities for that check: from the paths' summed costs, or a second pass on the "
     "mirrored pair (the default with --optimizer dp, which keeps no summed costs)",
     "lr-max-diff", "!-1", "validity.lr_source", [](const P& p) { return std::string(to_string(p.validity.lr_source)); },
     [](P& p, S t, S shown) { p.validity.lr_source = parse_choice(shown, [&] { return parse_lr_source(t); }); }},
    {"uniqueness", "uniqueness", K::kInt, "PCT", 0, 100, false, nullptr,
     "uniqueness margin in percent; 0 = off", "optimizer", "paths", "validity.uniqueness_pct",
     [](const P& p) { return std::to_string(p.validity.uniqueness_pct); },
     [](P& p, S t, S shown) { p.validity.uniqueness_pct = parse_int_text(shown, t); }},
    {"fill", "fill", K::kChoice, "background|none", 0, 0, false, "background|none",
     "invalid samples: filled from the background side, or left invalid", nullptr, nullptr, nullptr,
     [](const P& p) { return std::string(to_string(p.validity.fill)); },
     [](P& p, S t, S shown) { p.validity.fill = parse_choice(shown, [&] { return parse_fill_mode(t); }); }},
    {"min-confidence", "min_confidence", K::kInt, "C", 0, 255, false, nullptr,
     "samples with a confidence below C become invalid after the fill (0 = off; 128 = measured only; "
     "docs/model.md section 7)",
     nullptr, nullptr, "validity.min_confidence", [](const P& p) { return std::to_string(p.validity.min_confidence); },
     [](P& p, S t, S shown) { p.validity.min_confidence = parse_int_text(shown, t); }},
    {"support-prior", "support_prior", K::kInt, "LAMBDA", 0, kMaxPathPenaltyQ4, false, nullptr,
     "support prior: weak samples chosen again from the summed costs plus LAMBDA * min(|k - k_prior|, T), Q4 cost units; 0 = off (docs/model.md section 6b)", "optimizer", "paths", "prior.lambda_q4",
     [](const P& p) { return std::to_string(p.prior.lambda_q4); },
     [](P& p, S t, S shown) { p.prior.lambda_q4 = parse_int_text(shown, t); }},
    {"support-trunc", "support_trunc", K::kInt, "T", 1, 256, false, nullptr,
     "support prior: its penalty stops growing T disparities from the prior", "support-prior", "!0", "prior.trunc",
     [](const P& p) { return std::to_string(p.prior.trunc); },
     [](P& p, S t, S shown) { p.prior.trunc = parse_int_text(shown, t); }},
    {"support-conf", "support_conf", K::kInt, "C", 128, 255, false, nullptr,
     "support prior: measured samples with a confidence of at least C are the support", "support-prior", "!0", "prior.support_conf",
     [](const P& p) { return std::to_string(p.prior.support_conf); },
     [](P& p, S t, S shown) { p.prior.support_conf = parse_int_text(shown, t); }},
    {"support-uniqueness", "support_uniqueness", K::kInt, "PCT", 0, 100, false, nullptr,
     "support prior: uniqueness margin on the re-decided costs (0 = keep every new winner)", "support-prior", "!0", "prior.uniqueness_pct",
     [](const P& p) { return std::to_string(p.prior.uniqueness_pct); },
     [](P& p, S t, S shown) { p.prior.uniqueness_pct = parse_int_text(shown, t); }},
    {"plane-seg-fine", "plane_seg_fine", K::kInt, "DI", 0, 255, false, nullptr,
     "support prior: segments for the planes join mesh edges with |dI| <= DI (0 = no such level)", "support-prior", "!0", "prior.seg_fine",
     [](const P& p) { return std::to_string(p.prior.seg_fine); },
     [](P& p, S t, S shown) { p.prior.seg_fine = parse_int_text(shown, t); }},
    {"plane-seg-coarse", "plane_seg_coarse", K::kInt, "DI", 0, 255, false, nullptr,
     "support prior: a second, coarser segment level for the samples the first left without a plane (0 = none)", "support-prior", "!0", "prior.seg_coarse",
     [](const P& p) { return std::to_string(p.prior.seg_coarse); },
     [](P& p, S t, S shown) { p.prior.seg_coarse = parse_int_text(shown, t); }},
    {"plane-min", "plane_min", K::kInt, "N", 3, 65535, false, nullptr,
     "support prior: support samples a segment needs for a plane", "support-prior", "!0", "prior.plane_min",
     [](const P& p) { return std::to_string(p.prior.plane_min); },
     [](P& p, S t, S shown) { p.prior.plane_min = parse_int_text(shown, t); }},
    {"plane-tol", "plane_tol", K::kInt, "Q4", 1, 1024, false, nullptr,
     "support prior: a plane's inlier distance in 1/16 px", "support-prior", "!0", "prior.plane_tol_q4",
     [](const P& p) { return std::to_string(p.prior.plane_tol_q4); },
     [](P& p, S t, S shown) { p.prior.plane_tol_q4 = parse_int_text(shown, t); }},
    {"edge-spread", "edge_spread", K::kInt, "Q4", 0, 16 * kMaxNumDisp, false, nullptr,
     "interpolation: a triangle whose vertex disparities spread over more than this (1/16 px) straddles a "
     "depth edge, and its pixels take the disparity of the vertex nearest in intensity; 0 = the plane "
     "through the three everywhere (docs/model.md section 4)",
     "dense", "0", "interp.edge_spread_q4", [](const P& p) { return std::to_string(p.interp.edge_spread_q4); },
     [](P& p, S t, S shown) { p.interp.edge_spread_q4 = parse_int_text(shown, t); }},
    {"no-subpixel", "subpixel", K::kFlag, "", 0, 1, false, nullptr,
     "integer disparities only (Python: subpixel=False)", nullptr, nullptr, nullptr,
     [](const P& p) { return std::string(p.dp.subpixel ? "0" : "1"); },
     [](P& p, S, S) { p.dp.subpixel = false; }},
    {"subpixel-fit", "subpixel_fit", K::kChoice, "parabola|equiangular", 0, 0, false, "parabola|equiangular",
     "the curve through the costs at k-1, k, k+1 that gives the sub-pixel offset: a parabola, or the "
     "equiangular fit's symmetric V (docs/model.md section 3)",
     "no-subpixel", "0", "dp.subpixel_fit", [](const P& p) { return std::string(to_string(p.dp.subpixel_fit)); },
     [](P& p, S t, S shown) { p.dp.subpixel_fit = parse_choice(shown, [&] { return parse_subpixel_fit(t); }); }},
    {"dense", "dense", K::kFlag, "", 0, 1, false, nullptr, "every pixel a sample (the paper's dense baseline)",
     nullptr, nullptr, nullptr, [](const P& p) { return std::string(p.dense ? "1" : "0"); },
     [](P& p, S, S) { p.dense = true; }},
};

bool among(const std::string& value, const std::string& alternatives) {
  std::size_t start = 0;
  for (;;) {
    const std::size_t bar = alternatives.find('|', start);
    if (alternatives.compare(start, bar == std::string::npos ? std::string::npos : bar - start, value) == 0)
      return true;
    if (bar == std::string::npos) return false;
    start = bar + 1;
  }
}

// Whether `o` changes anything given the others: its needs_option's value in `p`.
bool has_effect(const ModelOption& o, const StereoParams& p) {
  if (!o.needs_option) return true;
  const std::string value = find_model_option(o.needs_option)->get(p);
  const std::string want = o.needs_values;
  return want[0] == '!' ? value != want.substr(1) : among(value, want);
}

// "--cost ad" or "cost='ad'" (numbers unquoted: "p1=120"); a flag's value
// ("1" given, "0" not) as "--no-subpixel" / "no --no-subpixel", or in Python
// the keyword's bool ("subpixel=False").
std::string shown_value(const ModelOption& o, const std::string& value, OptionSpelling s) {
  if (o.kind == ModelOptionKind::kFlag) {
    const bool given = value == "1";
    if (s == OptionSpelling::kCommandLine) return (given ? "" : "no ") + option_shown(o, s);
    const bool negated = std::string(o.name).rfind("no-", 0) == 0;
    return option_shown(o, s) + (given != negated ? "=True" : "=False");
  }
  if (s == OptionSpelling::kCommandLine) return option_shown(o, s) + " " + value;
  const bool text = o.kind == ModelOptionKind::kChoice && std::string(o.name) != "paths";
  return option_shown(o, s) + (text ? "='" + value + "'" : "=" + value);
}

}  // namespace

const std::vector<ModelOption>& model_options() { return kOptions; }

const ModelOption* find_model_option(const std::string& name) {
  for (const ModelOption& o : kOptions)
    if (name == o.name) return &o;
  return nullptr;
}

const ModelOption* find_model_option_keyword(const std::string& keyword) {
  for (const ModelOption& o : kOptions)
    if (keyword == o.keyword) return &o;
  return nullptr;
}

std::string option_shown(const ModelOption& o, OptionSpelling s) {
  return s == OptionSpelling::kCommandLine ? std::string("--") + o.name : std::string(o.keyword);
}

StereoParams model_params(const std::vector<GivenOption>& given, OptionSpelling spelling,
                          bool refuse_without_effect) {
  const auto given_text = [&](const char* name) -> const std::string* {
    for (const GivenOption& g : given)
      if (g.option == find_model_option(name)) return &g.text;
    return nullptr;
  };
  StereoParams p;
  if (const std::string* mode = given_text("mode")) {
    find_model_option("mode")->set(p, *mode, option_shown(*find_model_option("mode"), spelling));
    if (*mode == "paper") p = paper_params();
  }
  // Table order, whatever order they were given in.
  for (const ModelOption& o : kOptions) {
    if (std::string(o.name) == "mode") continue;
    if (const std::string* text = given_text(o.name)) o.set(p, *text, option_shown(o, spelling));
  }
  const ModelOption& ndisp = *find_model_option("ndisp");
  if (!given_text("ndisp"))
    bad(option_shown(ndisp, spelling) + (spelling == OptionSpelling::kCommandLine ? " D" : "") +
        " is required (number of disparities, 1.." + std::to_string(kMaxNumDisp) + ")");
  // The row DP keeps no summed costs: its left-right check needs the mirrored pass.
  if (!given_text("lr-source") && p.optimizer == Optimizer::kRowDp) p.validity.lr_source = LrSource::kMirroredPass;
  const ModelOption& max_area = *find_model_option("max-area");
  const ModelOption& min_area = *find_model_option("min-area");
  if (!given_text("min-area") && given_text("max-area") && p.tritree.max_area_px2 >= 1 &&
      p.tritree.min_area_px2 > largest_min_area_px2(p.tritree.max_area_px2)) {
    int needed = 1;  // the smallest A_max that allows it: a power of two >= 2 A_min
    while (needed < 2 * p.tritree.min_area_px2) needed *= 2;
    const std::string ma = option_shown(max_area, spelling);
    bad(shown_value(max_area, std::to_string(p.tritree.max_area_px2), spelling) +
        " is too small for the default minimum area of " + std::to_string(p.tritree.min_area_px2) +
        " px^2 (that needs " + ma + " >= " + std::to_string(needed) + "); add " +
        shown_value(min_area, "1", spelling));
  }
  try {
    validate_params(p);
  } catch (const Error& e) {
    if (e.code() != ErrorCode::kInvalidArgument) throw;
    bad(name_options_in(e.what(), spelling));
  }
  if (refuse_without_effect) {
    for (const GivenOption& g : given) {
      const ModelOption& o = *g.option;
      if (has_effect(o, p)) continue;
      const ModelOption& need = *find_model_option(o.needs_option);
      const std::string want = o.needs_values;
      std::string when;
      if (want[0] == '!') {
        when = option_shown(need, spelling) + " other than " + want.substr(1);
      } else {
        std::string alternatives;
        std::size_t start = 0;
        for (;;) {
          const std::size_t bar = want.find('|', start);
          if (!alternatives.empty()) alternatives += " or ";
          alternatives += shown_value(need, want.substr(start, bar == std::string::npos ? bar : bar - start),
                                      spelling);
          if (bar == std::string::npos) break;
          start = bar + 1;
        }
        when = alternatives;
      }
      // Say where a value nobody gave came from: the default or the paper mode.
      const std::string* mode = given_text("mode");
      const std::string origin = given_text(need.name) ? ""
                                 : mode && *mode == "paper"
                                     ? " (from " + shown_value(*find_model_option("mode"), "paper", spelling) + ")"
                                     : " (the default)";
      bad(option_shown(o, spelling) + " has no effect with " + shown_value(need, need.get(p), spelling) + origin +
          ": it is used only with " + when);
    }
    // The support prior works on the mesh: dense frames go without it (the
    // table's one condition per option is the optimizer or the prior's own).
    const ModelOption& dense = *find_model_option("dense");
    if (p.dense)
      for (const GivenOption& g : given) {
        const std::string fields = g.option->fields ? g.option->fields : "";
        if (fields.rfind("prior.", 0) != 0 || (std::string(g.option->name) == "support-prior" && p.prior.lambda_q4 == 0))
          continue;
        bad(option_shown(*g.option, spelling) + " has no effect with " + shown_value(dense, "1", spelling) +
            ": the support prior works on the mesh (sparse mode)");
      }
  }
  return p;
}

std::string name_options_in(const std::string& m, OptionSpelling spelling) {
  const std::size_t eq = m.find(" = ");
  const std::size_t sp = m.find(' ');
  // "field = value ..." or "field is not ..."
  const std::string field = m.substr(0, eq != std::string::npos && eq == sp ? eq : sp);
  const std::string rest = m.substr(eq != std::string::npos && eq == sp ? eq + 3 : sp + 1);
  for (const ModelOption& o : kOptions) {
    if (!o.fields) continue;
    const std::string fields = o.fields;
    std::size_t start = 0;
    for (;;) {
      const std::size_t semi = fields.find(';', start);
      const std::string entry = fields.substr(start, semi == std::string::npos ? semi : semi - start);
      const std::size_t part_at = entry.find('=');
      if (entry.substr(0, part_at) == field) {
        // "--p2 10 is out of range ..." on the command line, "p2 = 10 ..." in Python.
        std::string out = option_shown(o, spelling);
        if (part_at != std::string::npos) out += " " + entry.substr(part_at + 1);
        out += (spelling == OptionSpelling::kCommandLine || eq != sp ? " " : " = ") + rest;
        if (std::string(o.name) == "dmin")
          out += " (|" + option_shown(o, spelling) + "| + " + option_shown(*find_model_option("ndisp"), spelling) +
                 " must be at most " + std::to_string(kMaxDispSpan) + ")";
        return out;
      }
      if (semi == std::string::npos) break;
      start = semi + 1;
    }
  }
  return m;
}

std::string model_options_help() {
  const StereoParams defaults;
  const StereoParams paper = paper_params();
  constexpr std::size_t kColumn = 23, kWidth = 80;
  std::string out;
  for (const ModelOption& o : kOptions) {
    std::string text = o.help;
    if (o.kind == K::kInt)
      text += ", " + std::to_string(o.lo) + ".." + std::to_string(o.hi);
    else if (o.kind == K::kSize)
      text += " " + std::to_string(o.lo) + ".." + std::to_string(o.hi);
    else if (o.kind == K::kDecimal)
      text += ", " + tenths_text(static_cast<int>(o.lo)) + ".." + tenths_text(static_cast<int>(o.hi));
    if (std::string(o.name) == "ndisp") {
      text += " (required)";
    } else if (o.kind != K::kFlag) {
      const std::string d = o.get(defaults), pp = o.get(paper);
      text += " (default " + d + (std::string(o.name) != "mode" && pp != d ? "; paper " + pp : "") + ")";
    }
    std::string line = "  --" + std::string(o.name) + (o.metavar[0] ? " " + std::string(o.metavar) : "");
    line += line.size() + 1 < kColumn ? std::string(kColumn - line.size(), ' ') : "\n" + std::string(kColumn, ' ');
    // Words wrapped at kWidth, continuation lines at kColumn.
    std::size_t col = line.size() - line.rfind('\n') - 1;
    std::size_t start = 0;
    bool first = true;
    while (start < text.size()) {
      std::size_t end = text.find(' ', start);
      if (end == std::string::npos) end = text.size();
      const std::string word = text.substr(start, end - start);
      if (!first && col + 1 + word.size() > kWidth) {
        line += "\n" + std::string(kColumn, ' ');
        col = kColumn;
      } else if (!first) {
        line += ' ';
        ++col;
      }
      line += word;
      col += word.size();
      first = false;
      start = end + 1;
    }
    out += line + "\n";
  }
  return out;
}

}  // namespace tristereo
