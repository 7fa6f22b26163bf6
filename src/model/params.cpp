// Parameter validation: every bound of docs/model.md section 5 in one place.
#include <algorithm>
#include <string>

#include "tristereo/mesh.hpp"
#include "tristereo/params.hpp"
#include "tristereo/status.hpp"

namespace tristereo {

namespace {
[[noreturn]] void bad(const std::string& what) { throw Error(ErrorCode::kInvalidArgument, what); }

void check_range(const char* name, long long v, long long lo, long long hi) {
  if (v < lo || v > hi)
    bad(std::string(name) + " = " + std::to_string(v) + " is out of range [" + std::to_string(lo) +
        ", " + std::to_string(hi) + "]");
}

void check_window_side(const char* name, int v) {
  check_range(name, v, 1, kMaxWindowSide);
  if (v % 2 == 0) bad(std::string(name) + " = " + std::to_string(v) + " must be odd (the window is centred)");
}
}  // namespace

void validate_params(const StereoParams& p) {
  check_range("num_disp", p.num_disp, 1, kMaxNumDisp);
  // |d_min| + D <= 2048 keeps every Q4 disparity (16 d +- 8) inside int16 and
  // away from kInvalidDispQ4.
  check_range("d_min", p.d_min, -(kMaxDispSpan - p.num_disp), kMaxDispSpan - p.num_disp);
  check_range("tritree.psnr_deci_db", p.tritree.psnr_deci_db, kMinPsnrDeciDb, kMaxPsnrDeciDb);
  check_range("tritree.max_area_px2", p.tritree.max_area_px2, 1, kMaxAreaLimitPx2);
  if (p.tritree.min_area_px2 < 1 || p.tritree.min_area_px2 > largest_min_area_px2(p.tritree.max_area_px2))
    bad("tritree.min_area_px2 = " + std::to_string(p.tritree.min_area_px2) + " is out of range [1, " +
        std::to_string(largest_min_area_px2(p.tritree.max_area_px2)) +
        "] (at most half the largest power of two <= the maximum area, " +
        std::to_string(p.tritree.max_area_px2) + " px^2)");
  check_window_side("cost.window_w", p.cost.window_w);
  check_window_side("cost.window_h", p.cost.window_h);
  check_range("cost.truncation", p.cost.truncation, 1, 255);
  check_range("cost.asw_gamma_color", p.cost.asw_gamma_color, 1, 1000);
  check_range("cost.asw_gamma_proximity", p.cost.asw_gamma_proximity, 1, 100000);
  check_range("dp.lambda_q4", p.dp.lambda_q4, 0, kMaxLambdaQ4);
  if (p.cost.kind != CostKind::kAd) {
    check_range("cost.census_w", p.cost.census_w, 3, 9);
    check_range("cost.census_h", p.cost.census_h, 3, 9);
    if (p.cost.census_w % 2 == 0)
      bad("cost.census_w = " + std::to_string(p.cost.census_w) + " must be odd (the window is centred)");
    if (p.cost.census_h % 2 == 0)
      bad("cost.census_h = " + std::to_string(p.cost.census_h) + " must be odd (the window is centred)");
    if (p.cost.census_w * p.cost.census_h - 1 > kMaxCensusBits)
      bad("cost.census_h = " + std::to_string(p.cost.census_h) + " with a width of " +
          std::to_string(p.cost.census_w) + " gives " + std::to_string(p.cost.census_w * p.cost.census_h - 1) +
          " neighbours; the census descriptor holds at most " + std::to_string(kMaxCensusBits));
    if (p.cost.weights != Weights::kBox)
      bad("cost.weights = adaptive works with the ad cost only (census costs are box-aggregated)");
    check_range("cost.ad_weight_q4", p.cost.ad_weight_q4, 0, kMaxAdWeightQ4);
  }
  if (p.optimizer == Optimizer::kPaths) {
    if (p.paths.directions != 4 && p.paths.directions != 8)
      bad("paths.directions = " + std::to_string(p.paths.directions) + " must be 4 or 8");
    check_range("paths.p1_q4", p.paths.p1_q4, 0, kMaxPathPenaltyQ4);
    check_range("paths.p2_q4", p.paths.p2_q4, p.paths.p1_q4, kMaxPathPenaltyQ4);
    check_range("paths.p2_edge_scale", p.paths.p2_edge_scale, 0, 255);
    // Every path cost is <= max cost + P2, and the winner adds `directions`
    // of them in u16 lanes.
    const long long worst = static_cast<long long>(p.paths.directions) *
                            (max_cost_q4(p.cost) + p.paths.p2_q4);
    if (worst > 65534)
      bad("paths.p2_q4 = " + std::to_string(p.paths.p2_q4) + " is too large: " +
          std::to_string(p.paths.directions) + " directions x (largest cost " +
          std::to_string(max_cost_q4(p.cost)) + " + P2) = " + std::to_string(worst) +
          " exceeds 65534 (the summed path costs are 16-bit, 65535 marks no cost); lower P2 or the directions");
  }
  check_range("validity.lr_max_diff_q4", p.validity.lr_max_diff_q4, -1, 16 * kMaxNumDisp);
  if (p.validity.lr_source != LrSource::kSummedCosts && p.validity.lr_source != LrSource::kMirroredPass)
    bad("validity.lr_source is not an LrSource value");
  if (p.validity.lr_max_diff_q4 >= 0 && p.validity.lr_source == LrSource::kSummedCosts &&
      p.optimizer != Optimizer::kPaths)
    bad("validity.lr_source = costs needs the path optimizer (the row DP keeps no summed costs); "
        "use lr_source = mirror or turn the left-right check off");
  check_range("validity.uniqueness_pct", p.validity.uniqueness_pct, 0, 100);
  if (p.validity.fill != FillMode::kNone && p.validity.fill != FillMode::kBackground)
    bad("validity.fill is not a FillMode value");
  check_range("validity.min_confidence", p.validity.min_confidence, 0, 255);
  if (p.dp.subpixel_fit != SubpixelFit::kParabola && p.dp.subpixel_fit != SubpixelFit::kEquiangular)
    bad("dp.subpixel_fit is not a SubpixelFit value");
  // Support prior (docs/model.md section 6b). S'(k) = S(k) + lambda min(|k - kp|, T)
  // <= 65534 + 16000 * 256 < 2^23, so 16 (S'(k-1) - S'(k+1)) and 127 (R' - S') fit
  // 32 bits and 100 R' fits 64.
  check_range("prior.lambda_q4", p.prior.lambda_q4, 0, kMaxPathPenaltyQ4);
  check_range("prior.trunc", p.prior.trunc, 1, 256);
  check_range("prior.support_conf", p.prior.support_conf, kMinMeasuredConfidence, 255);
  check_range("prior.uniqueness_pct", p.prior.uniqueness_pct, 0, 100);
  check_range("prior.seg_fine", p.prior.seg_fine, 0, 255);
  check_range("prior.seg_coarse", p.prior.seg_coarse, 0, 255);
  check_range("prior.plane_min", p.prior.plane_min, 3, 65535);
  check_range("prior.plane_tol_q4", p.prior.plane_tol_q4, 1, 1024);
  check_range("interp.edge_spread_q4", p.interp.edge_spread_q4, 0, 16 * kMaxNumDisp);
}

bool support_prior_applies(const StereoParams& p) {
  return p.prior.lambda_q4 > 0 && p.optimizer == Optimizer::kPaths && !p.dense;
}

int max_cost_q4(const CostParams& c) {
  const int ad = 16 * c.truncation;
  const int census = 16 * (c.census_w * c.census_h - 1);
  switch (c.kind) {
    case CostKind::kAd: return ad;
    case CostKind::kCensus: return census;
    case CostKind::kAdCensus: return std::min(kMaxCostQ4, census + ((c.ad_weight_q4 * ad + 8) >> 4));
  }
  return kMaxCostQ4;
}

StereoParams paper_params() {
  StereoParams p;
  p.tritree.psnr_deci_db = 400;
  p.tritree.min_area_px2 = 1;
  p.optimizer = Optimizer::kRowDp;
  p.cost.kind = CostKind::kAd;
  p.cost.window_w = 5;
  p.cost.window_h = 5;
  p.cost.weights = Weights::kBox;
  p.cost.truncation = 30;
  p.dp = DpParams{};
  p.validity.lr_max_diff_q4 = -1;
  p.validity.uniqueness_pct = 0;
  p.validity.fill = FillMode::kBackground;
  p.prior.lambda_q4 = 0;
  p.interp.edge_spread_q4 = 0;
  return p;
}

const char* to_string(CostKind k) {
  switch (k) {
    case CostKind::kAd: return "ad";
    case CostKind::kCensus: return "census";
    case CostKind::kAdCensus: return "ad_census";
  }
  return "?";
}

const char* to_string(Optimizer o) { return o == Optimizer::kRowDp ? "dp" : "paths"; }
const char* to_string(FillMode f) { return f == FillMode::kNone ? "none" : "background"; }

CostKind parse_cost_kind(const std::string& s) {
  if (s == "ad") return CostKind::kAd;
  if (s == "census") return CostKind::kCensus;
  if (s == "ad_census") return CostKind::kAdCensus;
  bad("unknown cost '" + s + "' (expected ad, census or ad_census)");
}

Optimizer parse_optimizer(const std::string& s) {
  if (s == "dp") return Optimizer::kRowDp;
  if (s == "paths") return Optimizer::kPaths;
  bad("unknown optimizer '" + s + "' (expected dp or paths)");
}

FillMode parse_fill_mode(const std::string& s) {
  if (s == "none") return FillMode::kNone;
  if (s == "background") return FillMode::kBackground;
  bad("unknown fill '" + s + "' (expected none or background)");
}

const char* to_string(LrSource s) { return s == LrSource::kSummedCosts ? "costs" : "mirror"; }

LrSource parse_lr_source(const std::string& s) {
  if (s == "costs") return LrSource::kSummedCosts;
  if (s == "mirror") return LrSource::kMirroredPass;
  bad("unknown left-right source '" + s + "' (expected costs or mirror)");
}

const char* to_string(SubpixelFit f) { return f == SubpixelFit::kParabola ? "parabola" : "equiangular"; }

SubpixelFit parse_subpixel_fit(const std::string& s) {
  if (s == "parabola") return SubpixelFit::kParabola;
  if (s == "equiangular") return SubpixelFit::kEquiangular;
  bad("unknown sub-pixel fit '" + s + "' (expected parabola or equiangular)");
}

const char* to_string(Weights w) { return w == Weights::kBox ? "box" : "adaptive"; }

const char* to_string(GapPolicy g) {
  switch (g) {
    case GapPolicy::kInvSquare: return "inv_sq";
    case GapPolicy::kInverse: return "inv";
    case GapPolicy::kConstant: return "const";
  }
  return "?";
}

Weights parse_weights(const std::string& s) {
  if (s == "box") return Weights::kBox;
  if (s == "adaptive") return Weights::kAdaptive;
  bad("unknown weights '" + s + "' (expected box or adaptive)");
}

GapPolicy parse_gap_policy(const std::string& s) {
  if (s == "inv_sq") return GapPolicy::kInvSquare;
  if (s == "inv") return GapPolicy::kInverse;
  if (s == "const") return GapPolicy::kConstant;
  bad("unknown gap policy '" + s + "' (expected inv_sq, inv or const)");
}

const char* error_code_name(ErrorCode code) noexcept {
  switch (code) {
    case ErrorCode::kInvalidArgument: return "invalid argument";
    case ErrorCode::kSizeMismatch: return "size mismatch";
    case ErrorCode::kUnsupportedFormat: return "unsupported format";
    case ErrorCode::kCorruptFile: return "corrupt file";
    case ErrorCode::kIoError: return "I/O error";
    case ErrorCode::kNotConfigured: return "not configured";
    case ErrorCode::kPlatform: return "platform";
  }
  return "?";
}

}  // namespace tristereo
