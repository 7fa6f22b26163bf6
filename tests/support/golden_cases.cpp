#include "support/golden_cases.hpp"

#include "support/data.hpp"
#include "support/scenes.hpp"
#include "tristereo/synth.hpp"

namespace tristereo::test {

// Fixed parameters (not the defaults, so tuning the defaults does not move the digests).
// The paper's model (AD cost, row DP) with the parameters the goldens were
// first recorded with.
static StereoParams golden_params(int ndisp, bool dense, Weights w) {
  StereoParams p = paper_params();
  p.num_disp = ndisp;
  p.dense = dense;
  p.tritree.psnr_deci_db = 400;
  p.tritree.max_area_px2 = 100;
  p.tritree.min_area_px2 = 1;
  p.cost.window_w = 5;
  p.cost.window_h = 5;
  p.cost.weights = w;
  p.cost.truncation = 255;
  p.cost.asw_gamma_color = 10;
  p.cost.asw_gamma_proximity = 50;
  p.dp.lambda_q4 = 160;
  p.dp.gap = GapPolicy::kInverse;
  p.dp.subpixel = true;
  return p;
}

// The defaults (census, paths on the mesh, uniqueness, left-right check, background fill).
static StereoParams golden_defaults(int ndisp, bool dense) {
  StereoParams p;
  p.num_disp = ndisp;
  p.dense = dense;
  return p;
}

std::vector<GoldenCase> golden_cases(bool with_middlebury) {
  std::vector<GoldenCase> cases;
  for (std::uint32_t seed : {1u, 2u}) {
    SynthParams sp;
    sp.width = 160;
    sp.height = 120;
    sp.num_disp = 24;
    sp.seed = seed;
    const SyntheticScene s = make_synthetic_scene(sp);
    const std::string n = "synthetic" + std::to_string(seed);
    cases.push_back({n + "_sparse_box", s.left, s.right, golden_params(24, false, Weights::kBox)});
    cases.push_back({n + "_dense_box", s.left, s.right, golden_params(24, true, Weights::kBox)});
    cases.push_back({n + "_sparse_adaptive", s.left, s.right, golden_params(24, false, Weights::kAdaptive)});
    cases.push_back({n + "_sparse_default", s.left, s.right, golden_defaults(24, false)});
    cases.push_back({n + "_dense_default", s.left, s.right, golden_defaults(24, true)});
  }
  if (with_middlebury) {
    for (const std::string& name : test::middlebury_names()) {
      const test::MiddleburyPair m = test::load_middlebury(name);
      cases.push_back({name + "_sparse_box", m.left, m.right, golden_params(m.ndisp, false, Weights::kBox)});
      cases.push_back({name + "_sparse_adaptive", m.left, m.right, golden_params(m.ndisp, false, Weights::kAdaptive)});
      if (m.ndisp <= 20)  // tsukuba, venus: the defaults' frames on the two smaller scenes
        cases.push_back({name + "_sparse_default", m.left, m.right, golden_defaults(m.ndisp, false)});
    }
  }
  return cases;
}

std::vector<GoldenCase> golden_data_cases() {
  std::vector<GoldenCase> cases;
  for (const std::string set : {"middlebury2014", "kitti2015", "eth3d"})
    for (DataScene& s : load_data_set(set))
      cases.push_back({set + "/" + s.name + "_sparse_default", std::move(s.left), std::move(s.right),
                       golden_defaults(s.ndisp, false)});
  return cases;
}

}  // namespace tristereo::test
