#include "support/scenes.hpp"

#include <algorithm>
#include <cstdlib>

#include "tristereo/eval.hpp"
#include "tristereo/io.hpp"

namespace tristereo::test {

std::string middlebury_dir() { return data_set_dir("middlebury"); }

bool middlebury_available() { return data_set_available("middlebury"); }

std::vector<std::string> middlebury_names() { return {"tsukuba", "venus", "teddy", "cones"}; }

MiddleburyPair load_middlebury(const std::string& name) {
  MiddleburyPair p;
  p.name = name;
  for (const MiddleburyScene& s : read_datasets_tsv(middlebury_dir() + "/datasets.tsv"))
    if (s.name == name) {
      p.ndisp = s.ndisp;
      p.gt_scale = s.gt_scale;
    }
  const std::string dir = middlebury_dir() + "/" + name + "/";
  p.left = read_image_u8(dir + "left.png");
  p.right = read_image_u8(dir + "right.png");
  p.gt = load_middlebury_gt(dir + "disp_left.png", p.gt_scale);
  p.nonocc = read_image_u8(dir + "nonocc.png");
  p.all = read_image_u8(dir + "all.png");
  return p;
}

TritreeParams random_tritree_params(Rng& rng) {
  TritreeParams tp;
  const int areas[] = {1, 2, 7, 16, 100, 300, 1024};
  tp.max_area_px2 = areas[rng.uniform(0, 6)];
  tp.psnr_deci_db = rng.uniform(kMinPsnrDeciDb, kMaxPsnrDeciDb);
  tp.min_area_px2 = rng.uniform(1, largest_min_area_px2(tp.max_area_px2));
  return tp;
}

SyntheticScene synthetic_scene(int width, int height, int num_disp) {
  SynthParams sp;
  sp.width = width;
  sp.height = height;
  sp.num_disp = num_disp;
  return make_synthetic_scene(sp);
}

Mesh random_mesh(Rng& rng, int w, int h, Tritree& tree, TritreeParams* params) {
  const ImageU8 img = random_image(rng, w, h);
  const TritreeParams tp = random_tritree_params(rng);
  if (params != nullptr) *params = tp;
  tree.configure(w, h, tp);
  Mesh m;
  tree.build(img.view(), m);
  return m;
}

ImageU8 random_image(Rng& rng, int w, int h) {
  ImageU8 img(w, h, 1);
  const int gx = rng.uniform(-8, 8), gy = rng.uniform(-8, 8), base = rng.uniform(0, 255);
  const int noise = rng.uniform(0, 3) == 0 ? 0 : rng.uniform(1, 60);
  const int step_x = rng.uniform(0, w), step_v = rng.uniform(-100, 100);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      int v = base + gx * x + gy * y + (x >= step_x ? step_v : 0);
      if (noise) v += rng.uniform(-noise, noise);
      img.at(x, y) = static_cast<std::uint8_t>(std::clamp(v, 0, 255));
    }
  return img;
}

ImageU8 shifted_view(Rng& rng, const ImageU8& left, int shift, int noise) {
  ImageU8 r(left.width, left.height, 1);
  for (int y = 0; y < left.height; ++y)
    for (int x = 0; x < left.width; ++x) {
      const int sx = std::clamp(x + shift, 0, left.width - 1);
      int v = left.at(sx, y) + (noise ? rng.uniform(-noise, noise) : 0);
      r.at(x, y) = static_cast<std::uint8_t>(std::clamp(v, 0, 255));
    }
  return r;
}

PipelineConfig unpinned_config(int width, int height, const StereoParams& params, int threads,
                               KernelChoice kernels) {
  PipelineConfig c;
  c.max_width = width;
  c.max_height = height;
  c.params = params;
  c.kernels = kernels;
  c.threads = threads;
  c.pin_threads = false;
  return c;
}

Mesh tritree_mesh(Tritree& tree, const ImageU8& gray, int max_area_px2) {
  TritreeParams tp;
  tp.max_area_px2 = max_area_px2;
  tree.configure(gray.width, gray.height, tp);
  Mesh m;
  tree.build(gray.view(), m);
  return m;
}

StereoParams random_params(Rng& rng, int max_ndisp) {
  StereoParams p;
  p.num_disp = rng.uniform(1, max_ndisp);
  p.d_min = rng.uniform(-5, 5);
  p.dense = rng.uniform(0, 3) == 0;
  p.tritree.psnr_deci_db = rng.uniform(kMinPsnrDeciDb, kMaxPsnrDeciDb);
  p.tritree.max_area_px2 = rng.uniform(0, 1) ? rng.uniform(1, 40) : rng.uniform(1, kMaxAreaLimitPx2);
  // From the threshold's last digit rather than a draw of its own, so the
  // draws after it (and the kernels' coverage they give) stay as they were.
  p.tritree.min_area_px2 = std::min(1 + p.tritree.psnr_deci_db % 3, largest_min_area_px2(p.tritree.max_area_px2));
  p.cost.window_w = 2 * rng.uniform(0, 7) + 1;
  p.cost.window_h = 2 * rng.uniform(0, 7) + 1;
  p.cost.weights = rng.uniform(0, 1) ? Weights::kBox : Weights::kAdaptive;
  p.cost.truncation = rng.uniform(0, 2) ? 255 : rng.uniform(1, 255);
  p.cost.asw_gamma_color = rng.uniform(1, 40);
  p.cost.asw_gamma_proximity = rng.uniform(1, 200);
  p.dp.lambda_q4 = rng.uniform(0, 4) == 0 ? rng.uniform(0, kMaxLambdaQ4) : rng.uniform(0, 600);
  p.dp.gap = static_cast<GapPolicy>(rng.uniform(0, 2));
  p.dp.subpixel = rng.uniform(0, 1) == 1;
  // The matching stages beyond the paper (docs/model.md 2, 3b, 6).
  p.cost.kind = static_cast<CostKind>(rng.uniform(0, 2));
  if (p.cost.kind != CostKind::kAd) {
    p.cost.weights = Weights::kBox;
    do {
      p.cost.census_w = 2 * rng.uniform(1, 4) + 1;
      p.cost.census_h = 2 * rng.uniform(1, 4) + 1;
    } while (p.cost.census_w * p.cost.census_h - 1 > kMaxCensusBits);
    p.cost.ad_weight_q4 = rng.uniform(0, kMaxAdWeightQ4);
  }
  p.optimizer = rng.uniform(0, 2) == 0 ? Optimizer::kRowDp : Optimizer::kPaths;
  p.paths.directions = rng.uniform(0, 1) ? 8 : 4;
  const int p2_max = 65534 / p.paths.directions - max_cost_q4(p.cost);
  p.paths.p2_q4 = rng.uniform(0, std::min(p2_max, rng.uniform(0, 3) == 0 ? kMaxPathPenaltyQ4 : 2000));
  p.paths.p1_q4 = rng.uniform(0, p.paths.p2_q4);
  p.paths.p2_edge_scale = rng.uniform(0, 1) ? 0 : rng.uniform(1, 255);
  p.paths.gap = static_cast<GapPolicy>(rng.uniform(0, 2));
  p.validity.lr_max_diff_q4 = rng.uniform(0, 2) == 0 ? -1 : rng.uniform(0, 40);
  // From the summed costs needs the paths; the row DP takes the mirrored pass.
  p.validity.lr_source = p.optimizer == Optimizer::kPaths && rng.uniform(0, 1) == 1
                             ? LrSource::kSummedCosts
                             : LrSource::kMirroredPass;
  p.validity.uniqueness_pct = rng.uniform(0, 1) ? 0 : rng.uniform(1, 30);
  p.validity.fill = rng.uniform(0, 3) == 0 ? FillMode::kNone : FillMode::kBackground;
  // A third of the cases cut at a minimum confidence: filled ones (below
  // 128), measured ones, or both.
  p.validity.min_confidence = rng.uniform(0, 2) == 0 ? rng.uniform(1, 255) : 0;
  // From the threshold's digits rather than a draw of its own (as the minimum
  // area), so the draws of the callers (and the coverage they give) stay as they were.
  p.dp.subpixel_fit = (p.tritree.psnr_deci_db / 3) % 2 ? SubpixelFit::kEquiangular : SubpixelFit::kParabola;
  // The support prior (docs/model.md 6b), likewise from values drawn above:
  // off in a quarter of the cases, else any weight, levels and plane rules.
  const int g = p.cost.asw_gamma_proximity, c = p.cost.asw_gamma_color;
  p.prior.lambda_q4 = g % 4 == 0 ? 0 : 1 + (g * 37) % 2000;
  p.prior.trunc = 1 + c % 16;
  p.prior.support_conf = 128 + (c * 7) % 128;
  p.prior.uniqueness_pct = g % 41;
  p.prior.seg_fine = p.tritree.psnr_deci_db % 4;
  p.prior.seg_coarse = (g / 5) % 12;
  p.prior.plane_min = 3 + (g / 7) % 20;
  p.prior.plane_tol_q4 = 1 + (g / 3) % 48;
  // Depth edges (section 4): off in a fifth of the cases, else spreads from
  // a fraction of a pixel to several pixels.
  p.interp.edge_spread_q4 = c % 5 == 0 ? 0 : 1 + (c * 13 + g) % 160;
  return p;
}

}  // namespace tristereo::test
