// libFuzzer harness: the whole pipeline with parameters and pixels drawn from
// the input, checked against the float reference. For every kernel set this
// CPU runs, at a drawn thread count, the integer pipeline must give the
// reference's mesh, sample disparities and dense map bit for bit, or both must
// refuse the input with tristereo::Error.
//
// One input must run well under a second (under ASan + UBSan), and a frame
// costs about W * H * D * window_w * window_h (docs/model.md): the float
// reference takes ~1.8 us per such term with adaptive weights under the
// sanitizers (20x20, D = 17, 17x17 window: 3.6 s). So the drawn sizes are
// bounded: W, H <= 40, D <= 48, and the window is shrunk until
// W * H * D * w * h <= kWorkBudget (~0.3 s). Parameters are drawn one step beyond their
// valid ranges too, so validation is fuzzed alongside. TRISTEREO_FUZZ_VERBOSE=1
// prints what each input drew.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <algorithm>
#include <cstdlib>
#include <string>

#include "tests/fuzz/fuzz_input.hpp"
#include "tests/fuzz/fuzz_support.hpp"
#include "tristereo/kernels.hpp"
#include "tristereo/params.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/reference.hpp"
#include "tristereo/verify.hpp"

using namespace tristereo;
using namespace tristereo::fuzz;

namespace {

constexpr int kMaxSide = 40;
constexpr int kMaxDraw = 48;  // largest num_disp drawn
constexpr std::int64_t kWorkBudget = 150000;

// Valid parameters, then (one input in about three) one field pushed just
// outside its range, so validation is fuzzed too without making most inputs
// invalid. An exhausted input draws the low ends: a valid set.
StereoParams draw_params(FuzzInput& in) {
  StereoParams p;
  p.num_disp = in.int_in(1, kMaxDraw);
  p.d_min = in.int_in(0, 3) != 3 ? in.int_in(-8, 8)
                                  : in.int_in(-(kMaxDispSpan - p.num_disp), kMaxDispSpan - p.num_disp);
  p.dense = in.flag();
  p.tritree.psnr_deci_db = in.int_in(kMinPsnrDeciDb, kMaxPsnrDeciDb);
  p.tritree.max_area_px2 = in.flag() ? in.int_in(1, 40) : in.int_in(1, kMaxAreaLimitPx2);
  p.cost.window_w = 2 * in.int_in(0, kMaxWindowSide / 2) + 1;
  p.cost.window_h = 2 * in.int_in(0, kMaxWindowSide / 2) + 1;
  p.cost.weights = in.flag() ? Weights::kAdaptive : Weights::kBox;
  p.cost.truncation = in.int_in(1, 255);
  p.cost.asw_gamma_color = in.int_in(1, 1000);
  p.cost.asw_gamma_proximity = in.int_in(1, 100000);
  p.dp.lambda_q4 = in.flag() ? in.int_in(0, 600) : in.int_in(0, kMaxLambdaQ4);
  p.dp.gap = static_cast<GapPolicy>(in.int_in(0, 2));
  p.dp.subpixel = in.flag();
  // The stages beyond the paper (docs/model.md 2, 3b, 6): every field drawn.
  p.cost.kind = static_cast<CostKind>(in.int_in(0, 2));
  if (p.cost.kind != CostKind::kAd) {
    p.cost.weights = Weights::kBox;  // adaptive weights are for the AD cost only
    do {
      p.cost.census_w = 2 * in.int_in(1, 4) + 1;
      p.cost.census_h = 2 * in.int_in(1, 4) + 1;
    } while (p.cost.census_w * p.cost.census_h - 1 > kMaxCensusBits && in.remaining() > 0);
    if (p.cost.census_w * p.cost.census_h - 1 > kMaxCensusBits) p.cost.census_h = 3;
    p.cost.ad_weight_q4 = in.int_in(0, kMaxAdWeightQ4);
  }
  p.optimizer = in.flag() ? Optimizer::kRowDp : Optimizer::kPaths;
  p.paths.directions = in.flag() ? 8 : 4;
  const int p2_max = 65534 / p.paths.directions - max_cost_q4(p.cost);
  p.paths.p2_q4 = in.int_in(0, std::min(p2_max, in.flag() ? kMaxPathPenaltyQ4 : 2000));
  p.paths.p1_q4 = in.int_in(0, p.paths.p2_q4);
  p.paths.p2_edge_scale = in.flag() ? 0 : in.int_in(1, 255);
  p.paths.gap = static_cast<GapPolicy>(in.int_in(0, 2));
  p.validity.lr_max_diff_q4 = in.flag() ? -1 : in.int_in(0, 40);
  p.validity.lr_source = p.optimizer == Optimizer::kPaths && in.flag() ? LrSource::kSummedCosts
                                                                       : LrSource::kMirroredPass;
  p.validity.uniqueness_pct = in.flag() ? 0 : in.int_in(1, 30);
  p.validity.fill = in.flag() ? FillMode::kNone : FillMode::kBackground;
  p.dp.subpixel_fit = in.flag() ? SubpixelFit::kEquiangular : SubpixelFit::kParabola;
  // The support prior (docs/model.md 6b), from fields drawn above rather than
  // bytes of its own, so that the corpus's inputs keep every other field: the
  // adaptive weights' gammas and the truncation (both wide draws, used by
  // few models).
  const int g = p.cost.asw_gamma_proximity, c = p.cost.asw_gamma_color;
  p.prior.lambda_q4 = g % 4 == 0 ? 0 : 1 + g % (g % 3 == 0 ? kMaxPathPenaltyQ4 : 2000);
  p.prior.trunc = 1 + c % 32;
  p.prior.support_conf = 128 + (c * 7) % 128;
  p.prior.uniqueness_pct = p.cost.truncation % 51;
  p.prior.seg_fine = p.tritree.psnr_deci_db % 5;
  p.prior.seg_coarse = p.prior.seg_fine + (g / 5) % 9;
  p.prior.plane_min = 3 + (g / 7) % 30;
  p.prior.plane_tol_q4 = 1 + (g / 3) % 64;
  // Depth edges (section 4): off in a fifth of the inputs, else any spread
  // from a single step to the whole range.
  p.interp.edge_spread_q4 = c % 5 == 0 ? 0 : 1 + (c * 13 + g) % (16 * kMaxNumDisp);
  const bool above = in.flag();
  switch (in.int_in(0, 53)) {  // 25 of 54: not quite one input in two
    case 1: p.num_disp = above ? kMaxNumDisp + 1 : 0; break;
    case 2: p.d_min = above ? kMaxDispSpan - p.num_disp + 1 : -(kMaxDispSpan - p.num_disp) - 1; break;
    case 3: p.tritree.psnr_deci_db = above ? kMaxPsnrDeciDb + 1 : kMinPsnrDeciDb - 1; break;
    case 4: p.tritree.max_area_px2 = above ? kMaxAreaLimitPx2 + 1 : 0; break;
    case 5: p.cost.window_w = above ? p.cost.window_w + 1 : -1; break;  // even, or < 1
    case 6: p.cost.window_h = above ? kMaxWindowSide + 2 : 0; break;
    case 7: p.cost.truncation = above ? 256 : 0; break;
    case 8: p.cost.asw_gamma_color = above ? 1001 : 0; break;
    case 9: p.cost.asw_gamma_proximity = above ? 100001 : 0; break;
    case 10: p.dp.lambda_q4 = above ? kMaxLambdaQ4 + 1 : -1; break;
    case 11: p.cost.census_w = above ? 11 : 2; break;
    case 12: p.cost.ad_weight_q4 = above ? kMaxAdWeightQ4 + 1 : -1; break;
    case 13: p.paths.directions = above ? 16 : 2; break;
    case 14: p.paths.p2_q4 = above ? p2_max + 1 : p.paths.p1_q4 - 1; break;  // the u16 bound, or P2 < P1
    case 15: p.paths.p2_edge_scale = above ? 256 : -1; break;
    case 16: p.validity.lr_max_diff_q4 = above ? 16 * kMaxNumDisp + 1 : -2; break;
    case 17: p.validity.uniqueness_pct = above ? 101 : -1; break;
    case 18:  // the summed-costs check with the row DP, or a weight kind census does not take
      if (above) {
        p.optimizer = Optimizer::kRowDp;
        p.validity.lr_source = LrSource::kSummedCosts;
        p.validity.lr_max_diff_q4 = 16;
      } else {
        p.cost.kind = CostKind::kCensus;
        p.cost.weights = Weights::kAdaptive;
      }
      break;
    case 19: p.dp.subpixel_fit = static_cast<SubpixelFit>(above ? 2 : -1); break;  // no such fit
    case 20: p.prior.lambda_q4 = above ? kMaxPathPenaltyQ4 + 1 : -1; break;
    case 21: p.prior.trunc = above ? 257 : 0; break;
    case 22: p.prior.support_conf = above ? 256 : 127; break;
    case 23: p.prior.plane_min = above ? 65536 : 2; break;
    case 24: p.prior.plane_tol_q4 = above ? 1025 : 0; break;
    case 25: p.interp.edge_spread_q4 = above ? 16 * kMaxNumDisp + 1 : -1; break;
    default: break;  // valid
  }
  return p;
}

// Keeps W * H * D * w * h within the budget by shrinking the window (odd
// sides stay odd, so a valid window stays valid).
void bound_work(StereoParams& p, int w, int h) {
  const std::int64_t per_window = std::int64_t{w} * h * (p.num_disp > 0 ? p.num_disp : 1);
  while (per_window * p.cost.window_w * p.cost.window_h > kWorkBudget &&
         (p.cost.window_w > 2 || p.cost.window_h > 2) && p.cost.window_w > 0 && p.cost.window_h > 0) {
    if (p.cost.window_w >= p.cost.window_h) p.cost.window_w -= 2;
    else p.cost.window_h -= 2;
  }
}

// Pixels from the input; once it runs out, from a generator seeded by what
// was drawn, so short inputs still give textured images.
struct PixelSource {
  FuzzInput& in;
  std::uint32_t state;
  std::uint8_t next() {
    if (in.remaining() > 0) return in.byte();
    state = state * 1664525u + 1013904223u;
    return static_cast<std::uint8_t>(state >> 24);
  }
};

// A copy of img with `pad` bytes after every row, viewed through that stride.
struct PaddedImage {
  std::vector<std::uint8_t> bytes;
  ImageView<const std::uint8_t> view;
  PaddedImage(const ImageU8& img, int pad) {
    const std::ptrdiff_t row = static_cast<std::ptrdiff_t>(img.width) * img.channels;
    const std::ptrdiff_t stride = row + pad;
    bytes.assign(static_cast<std::size_t>(stride) * img.height, 0xA5);
    for (int y = 0; y < img.height; ++y)
      std::copy(img.row(y), img.row(y) + row, bytes.begin() + stride * y);
    view = {bytes.data(), img.width, img.height, img.channels, stride};
  }
};

std::string describe(const StereoParams& p, int w, int h, int c) {
  return std::to_string(w) + "x" + std::to_string(h) + "x" + std::to_string(c) +
         " D=" + std::to_string(p.num_disp) + " dmin=" + std::to_string(p.d_min) +
         " dense=" + std::to_string(p.dense) + " window=" + std::to_string(p.cost.window_w) + "x" +
         std::to_string(p.cost.window_h) + " weights=" + to_string(p.cost.weights) + " cost=" +
         to_string(p.cost.kind) + " census=" + std::to_string(p.cost.census_w) + "x" + std::to_string(p.cost.census_h) +
         " optimizer=" + to_string(p.optimizer) + " paths=" + std::to_string(p.paths.directions) + " p1=" +
         std::to_string(p.paths.p1_q4) + " p2=" + std::to_string(p.paths.p2_q4) + " lr=" +
         std::to_string(p.validity.lr_max_diff_q4) + "/" + to_string(p.validity.lr_source) + " uniq=" +
         std::to_string(p.validity.uniqueness_pct) + " fill=" + to_string(p.validity.fill) + " prior=" +
         std::to_string(p.prior.lambda_q4) + "/" + std::to_string(p.prior.seg_fine) + "," +
         std::to_string(p.prior.seg_coarse);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzInput in(data, size);
  const int w = in.int_in(2, kMaxSide), h = in.int_in(2, kMaxSide);
  const int channels = in.flag() ? 3 : 1;
  StereoParams p = draw_params(in);
  bound_work(p, w, h);
  const int threads = in.int_in(1, 3);
  const int extra_w = in.int_in(0, 7), extra_h = in.int_in(0, 7);  // configured > frame
  const int pad_left = in.int_in(0, 7), pad_right = in.int_in(0, 7);
  const bool shifted = in.flag();  // right = left shifted (plus input noise)
  const int shift = in.int_in(0, 15);

  PixelSource px{in, static_cast<std::uint32_t>(w * 131 + h * 7 + p.num_disp)};
  ImageU8 left(w, h, channels), right(w, h, channels);
  for (auto& v : left.pixels) v = px.next();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < channels; ++c) {
        const std::uint8_t noise = px.next();
        right.at(x, y, c) = shifted ? static_cast<std::uint8_t>(
                                          (x + shift < w ? left.at(x + shift, y, c) : noise) +
                                          (noise & 3))
                                    : noise;
      }

  const std::string what = describe(p, w, h, channels);
  StereoOutput ref;
  const bool ref_ok = library_call("run_reference", [&] { ref = run_reference(left, right, p); });
  std::string refusal;
  const bool valid = library_call("validate_params", [&] {
    try {
      validate_params(p);
    } catch (const Error& e) {
      refusal = e.what();
      throw;
    }
  });
  static const bool verbose = std::getenv("TRISTEREO_FUZZ_VERBOSE") != nullptr;
  if (verbose) std::fprintf(stderr, "pipeline: %s: %s\n", what.c_str(), valid ? "valid" : refusal.c_str());
  TRISTEREO_FUZZ_CHECK(ref_ok == valid, "reference and validate_params disagree: " + what);

  const PaddedImage l(left, pad_left), r(right, pad_right);
  for (KernelChoice k : available_kernel_sets()) {
    PipelineConfig config;
    config.max_width = w + extra_w;
    config.max_height = h + extra_h;
    config.params = p;
    config.kernels = k;
    config.threads = threads;
    config.pin_threads = false;
    Pipeline pipeline;
    const bool configured = library_call("configure", [&] { pipeline.configure(config); });
    TRISTEREO_FUZZ_CHECK(configured == valid, std::string("configure vs validate_params, ") +
                                                  to_string(k) + ": " + what);
    if (!configured) continue;
    // Twice: the second frame reuses every buffer the first one filled.
    for (int round = 0; round < 2; ++round) {
      std::string diff;
      const bool processed = library_call("process", [&] {
        diff = first_difference(ref, pipeline.process(l.view, r.view));
      });
      TRISTEREO_FUZZ_CHECK(processed == ref_ok, std::string("process vs reference, ") +
                                                    to_string(k) + ": " + what);
      TRISTEREO_FUZZ_CHECK(diff.empty(), std::string(to_string(k)) + ", " + std::to_string(threads) +
                                             " thread(s), " + what + ": " + diff);
    }
  }
  return 0;
}
