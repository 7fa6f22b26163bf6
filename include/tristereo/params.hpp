// Parameters of the stereo model (docs/model.md defines each one exactly).
//
// All parameters are integers or are quantised once by validate_params(); the
// integer path and the float reference consume the same quantised values, so a
// configuration decides identically on both. validate_params() rejects every
// configuration whose integer sums could overflow (see docs/model.md, "Bounds").
#pragma once

#include "tristereo/export.hpp"

#include <cstdint>
#include <string>

namespace tristereo {

// Hard limits. Image size bounds keep every tritree and interpolation sum
// inside the integer widths documented in docs/model.md.
constexpr int kMaxImageSide = 4096;
constexpr int kMaxNumDisp = 256;
constexpr int kMaxDispSpan = 2048;    // |d_min| + num_disp, so 16 d fits int16
constexpr int kMaxWindowSide = 31;
constexpr int kMaxAreaLimitPx2 = 1024;
constexpr int kMinPsnrDeciDb = 100;   // 10.0 dB
constexpr int kMaxPsnrDeciDb = 700;   // 70.0 dB
constexpr int kMaxLambdaQ4 = 32000;

enum class Weights { kBox, kAdaptive };
// Gap policy tau(g) of the smoothness term P(g) = round(lambda * tau(g)).
enum class GapPolicy { kInvSquare, kInverse, kConstant };

struct TritreeParams {
  int psnr_deci_db = 400;   // split when PSNR of the plane fit < this / 10 dB
  int max_area_px2 = 100;   // split when area > this
};

struct CostParams {
  int window_w = 5;                 // odd, 1..kMaxWindowSide
  int window_h = 5;                 // odd, 1..kMaxWindowSide
  Weights weights = Weights::kBox;
  int truncation = 30;              // T_c: |L-R| is clamped to this (1..255; 255 = none)
  int asw_gamma_color = 10;         // adaptive weights: exp(-|dI| / gamma_color)
  int asw_gamma_proximity = 50;     // adaptive weights: exp(-(dx^2+dy^2) / gamma_proximity)
};

struct DpParams {
  int lambda_q4 = 40;               // smoothness weight, in Q4 cost units
  GapPolicy gap = GapPolicy::kConstant;  // measured best, see docs/tuning.md
  bool subpixel = true;             // parabola refinement to Q4
};

struct StereoParams {
  int d_min = 0;                    // smallest disparity searched
  int num_disp = 64;                // D: disparities d_min .. d_min + D - 1
  bool dense = false;               // every pixel a DP sample (paper's baseline)
  TritreeParams tritree;
  CostParams cost;
  DpParams dp;
};

// Throws tristereo::Error(kInvalidArgument) naming the first bad field.
TRISTEREO_API void validate_params(const StereoParams& params);

TRISTEREO_API const char* to_string(Weights w);
TRISTEREO_API const char* to_string(GapPolicy g);
TRISTEREO_API Weights parse_weights(const std::string& s);    // "box" | "adaptive"
TRISTEREO_API GapPolicy parse_gap_policy(const std::string& s);  // "inv_sq" | "inv" | "const"

}  // namespace tristereo
