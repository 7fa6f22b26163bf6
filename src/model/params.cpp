// Parameter validation: every bound of docs/model.md section 5 in one place.
#include <string>

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
  check_window_side("cost.window_w", p.cost.window_w);
  check_window_side("cost.window_h", p.cost.window_h);
  check_range("cost.truncation", p.cost.truncation, 1, 255);
  check_range("cost.asw_gamma_color", p.cost.asw_gamma_color, 1, 1000);
  check_range("cost.asw_gamma_proximity", p.cost.asw_gamma_proximity, 1, 100000);
  check_range("dp.lambda_q4", p.dp.lambda_q4, 0, kMaxLambdaQ4);
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
