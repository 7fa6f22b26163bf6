// Parameters of the stereo model (docs/model.md defines each one exactly).
//
// All parameters are integers or are quantised once by validate_params(); the
// integer path and the float reference consume the same quantised values, so a
// configuration decides identically on both. validate_params() rejects every
// configuration whose integer sums could overflow (see docs/model.md, "Bounds").
#pragma once

#include "tristereo/export.hpp"
#include "tristereo/fixed_point.hpp"

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
constexpr int kMaxCensusBits = 64;    // census window w * h - 1 (descriptor bits)
constexpr int kMaxAdWeightQ4 = 64;    // AD share of the ad_census cost, Q4 (4.0)
constexpr int kMaxPathPenaltyQ4 = 16000;

enum class Weights { kBox, kAdaptive };
// Per-pixel matching cost (docs/model.md section 2): the paper's truncated
// absolute difference, the census transform's Hamming distance (robust to gain,
// offset and gamma differences between the cameras), or both added.
enum class CostKind { kAd, kCensus, kAdCensus };
// How sample disparities are chosen from the costs (docs/model.md section 3):
// the paper's exact DP along each row, or path costs summed over several
// directions on the mesh (semi-global style).
enum class Optimizer { kRowDp, kPaths };
// What becomes of samples that the validity checks reject (docs/model.md section 6).
enum class FillMode { kNone, kBackground };
// Where the left-right check takes the right view's disparities from
// (docs/model.md section 6): the path optimizer's summed costs read along the
// right image's rows (no second pass), or a second matching pass on the
// mirrored pair.
enum class LrSource { kSummedCosts, kMirroredPass };
// Gap policy tau(g) of the smoothness term P(g) = round(lambda * tau(g)).
enum class GapPolicy { kInvSquare, kInverse, kConstant };
// The curve fitted through a sample's costs at k-1, k, k+1 for its sub-pixel
// offset (docs/model.md section 3): a parabola, or the symmetric V of the
// equiangular fit (lines of opposite slopes through the three costs).
enum class SubpixelFit { kParabola, kEquiangular };

// The largest TritreeParams::min_area_px2 allowed with this max_area_px2: half
// the largest power of two <= max_area_px2 (at least 1), so that a triangle
// larger than A_max, stretched or not, is never kept whole by the minimum area.
constexpr int largest_min_area_px2(int max_area_px2) {
  int p = 1;
  while (p * 2 <= max_area_px2) p *= 2;
  return p >= 2 ? p / 2 : 1;
}

struct TritreeParams {
  int psnr_deci_db = 440;   // split when PSNR of the plane fit < this / 10 dB
  int max_area_px2 = 100;   // split when area > this
  // Only triangles whose children would have at least this area want to split
  // (the paper's minimum area; 1 = down to 1 px^2 leaves, the paper mode's).
  // 1..largest_min_area_px2(max_area_px2).
  int min_area_px2 = 2;
};

struct CostParams {
  CostKind kind = CostKind::kCensus;
  int census_w = 5;                 // census transform window, odd, 3..9, census_w * census_h - 1 <= 64
  int census_h = 5;
  int ad_weight_q4 = 8;             // ad_census: cost = census + ad_weight_q4 * ad / 16 (0..64)
  int window_w = 3;                 // support window (aggregation), odd, 1..kMaxWindowSide
  int window_h = 3;                 // odd, 1..kMaxWindowSide (the paper's model: 5x5)
  Weights weights = Weights::kBox;
  int truncation = 30;              // T_c: |L-R| is clamped to this (1..255; 255 = none)
  int asw_gamma_color = 10;         // adaptive weights: exp(-|dI| / gamma_color)
  int asw_gamma_proximity = 50;     // adaptive weights: exp(-(dx^2+dy^2) / gamma_proximity)
};

struct DpParams {
  int lambda_q4 = 40;               // smoothness weight, in Q4 cost units
  GapPolicy gap = GapPolicy::kConstant;  // measured best, see docs/tuning.md
  bool subpixel = true;             // sub-pixel refinement to Q4 (both optimizers)
  SubpixelFit subpixel_fit = SubpixelFit::kParabola;  // its curve, when subpixel
};

// Path aggregation on the samples (docs/model.md section 3b): P1 for a
// one-step disparity change along a path, P2 for larger jumps, in Q4 cost
// units. Each sample's predecessor along a direction is its mesh neighbour
// that best follows the direction (the same-row sample for horizontal ones).
struct PathParams {
  int directions = 4;               // 4 (horizontal, vertical) or 8 (+ diagonals)
  int p1_q4 = 120;
  int p2_q4 = 800;                  // >= p1_q4
  // P2 shrinks across intensity edges: P2' = P1 + (P2 - P1) * T / (T + |I(p) - I(q)|);
  // 0 = off (P2 everywhere).
  int p2_edge_scale = 30;
  GapPolicy gap = GapPolicy::kConstant;  // P1, P2 scaled by tau(edge length)
};

// Validity of sample disparities (docs/model.md section 6).
struct ValidityParams {
  // Left-right check: a sample is kept when the right view's disparity at its
  // match agrees within lr_max_diff_q4 (Q4). -1 = no check.
  int lr_max_diff_q4 = 16;
  // kSummedCosts needs optimizer = kPaths (the row DP keeps no summed costs).
  LrSource lr_source = LrSource::kSummedCosts;
  // Uniqueness: the best summed cost times (100 + margin) must stay below 100 times
  // every cost two or more disparities away. 0 = off.
  int uniqueness_pct = 20;
  FillMode fill = FillMode::kBackground;
  // After the fill, samples whose confidence (docs/model.md section 7) is
  // below this become invalid, 0..255. 0 = off; 1 changes nothing; 128 keeps
  // measured samples only.
  int min_confidence = 0;
};

// Support prior (docs/model.md section 6b; issue 40): samples that are
// measured with a confidence of at least support_conf are the *support*; every
// other sample in a segment of similar intensity on the mesh whose support
// lies on a plane gets that plane's disparity as its prior, and its winner is
// chosen again from the summed path costs plus lambda * min(|k - k_prior|,
// trunc). It applies to the path optimizer in sparse mode
// (support_prior_applies); dense frames and the row DP go without it.
struct SupportPriorParams {
  int lambda_q4 = 300;     // 0 = off; 1..16000 Q4 cost units per disparity step
  int trunc = 8;           // 1..256: the prior's penalty stops growing this many steps away
  int support_conf = 160;  // 128..255
  int uniqueness_pct = 20; // on the re-decided costs, 0..100 (0 = keep every new winner)
  int seg_fine = 2;        // 0..255: segments join mesh edges with |dI| <= this (0 = no level)
  int seg_coarse = 8;      // 0..255: a second level for samples the first left without a plane
  int plane_min = 10;      // 3..65535 support samples a segment needs for a plane
  int plane_tol_q4 = 16;   // 1..1024: inlier distance (2x for the refits), Q4
};

// Interpolation of the dense map from the samples (docs/model.md section 4).
// A triangle whose vertex disparities spread over more than edge_spread_q4
// straddles a depth edge: its pixels take the disparity of the vertex nearest
// to them in intensity instead of the plane through the three (sparse mode).
struct InterpParams {
  int edge_spread_q4 = 48;  // 0..4096 Q4; 0 = planes everywhere (the paper's model)
};

struct StereoParams {
  int d_min = 0;                    // smallest disparity searched
  int num_disp = 64;                // D: disparities d_min .. d_min + D - 1
  bool dense = false;               // every pixel a DP sample (paper's baseline)
  Optimizer optimizer = Optimizer::kPaths;
  TritreeParams tritree;
  CostParams cost;
  DpParams dp;                      // optimizer = kRowDp
  PathParams paths;                 // optimizer = kPaths
  ValidityParams validity;
  SupportPriorParams prior;         // applies with optimizer = kPaths, sparse
  InterpParams interp;              // sparse mode
};

// The paper's model (Sarkis & Diepold 2008): AD cost, one DP per row, no
// validity checks. Every improvement is measured against it.
TRISTEREO_API StereoParams paper_params();

// Largest matching cost (Q4) the cost kind can produce with these parameters.
TRISTEREO_API int max_cost_q4(const CostParams& cost);

// Throws tristereo::Error(kInvalidArgument) naming the first bad field.
TRISTEREO_API void validate_params(const StereoParams& params);

// True when the support prior runs: lambda > 0, the path optimizer (its
// summed costs) and sparse mode (the mesh's segments).
TRISTEREO_API bool support_prior_applies(const StereoParams& params);

TRISTEREO_API const char* to_string(Weights w);
TRISTEREO_API const char* to_string(GapPolicy g);
TRISTEREO_API Weights parse_weights(const std::string& s);    // "box" | "adaptive"
TRISTEREO_API GapPolicy parse_gap_policy(const std::string& s);  // "inv_sq" | "inv" | "const"
TRISTEREO_API const char* to_string(CostKind k);
TRISTEREO_API const char* to_string(Optimizer o);
TRISTEREO_API const char* to_string(FillMode f);
TRISTEREO_API CostKind parse_cost_kind(const std::string& s);   // "ad" | "census" | "ad_census"
TRISTEREO_API Optimizer parse_optimizer(const std::string& s);  // "dp" | "paths"
TRISTEREO_API FillMode parse_fill_mode(const std::string& s);   // "none" | "background"
TRISTEREO_API const char* to_string(LrSource s);
TRISTEREO_API LrSource parse_lr_source(const std::string& s);   // "costs" | "mirror"
TRISTEREO_API const char* to_string(SubpixelFit f);
TRISTEREO_API SubpixelFit parse_subpixel_fit(const std::string& s);  // "parabola" | "equiangular"

}  // namespace tristereo
