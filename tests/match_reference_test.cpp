// Integer matching path (MatchContext + RowMatcher, every available kernel
// set) == float reference (src/reference/ref_match.hpp), bit for bit: rows of
// the four Middlebury scenes and many random small images x random parameters.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "src/cost/match_context.hpp"
#include "src/dp/row_matcher.hpp"
#include "src/kernels/dispatch.hpp"
#include "src/reference/ref_match.hpp"
#include "tristereo/gray.hpp"
#include "tristereo/io.hpp"
#include "tristereo/kernels.hpp"
#include "support/data.hpp"

namespace tristereo {
namespace {

// Every row of `ys` at samples `xs`, through the integer path with `kernels`.
std::vector<std::vector<std::int16_t>> integer_rows(const ImageU8& left, const ImageU8& right,
                                                    const StereoParams& p, const KernelSet& kernels,
                                                    const std::vector<int>& ys,
                                                    const std::vector<int>& xs) {
  MatchContext ctx(left.width, left.height, p, kernels);
  ctx.begin_frame(left.view(), right.view());
  // Two bands, as two workers would prepare them.
  CensusScratch census;
  census.resize(left.width);
  ctx.prepare_right_rows(0, left.height / 2, &census);
  ctx.prepare_right_rows(left.height / 2, left.height, &census);
  RowMatcher matcher(left.width, p);
  const std::vector<std::int32_t> xs32(xs.begin(), xs.end());
  std::vector<std::vector<std::int16_t>> rows;
  for (int y : ys) {
    std::vector<std::int16_t> d(xs.size());
    matcher.match_row(ctx, y, xs32.data(), static_cast<int>(xs32.size()), d.data());
    rows.push_back(d);
  }
  return rows;
}

std::string describe(const StereoParams& p) {
  std::ostringstream s;
  s << "d_min " << p.d_min << " D " << p.num_disp << " win " << p.cost.window_w << "x"
    << p.cost.window_h << " " << to_string(p.cost.weights) << " T " << p.cost.truncation
    << " gc " << p.cost.asw_gamma_color << " gp " << p.cost.asw_gamma_proximity << " lambda "
    << p.dp.lambda_q4 << " " << to_string(p.dp.gap) << " sub " << p.dp.subpixel << " "
    << to_string(p.dp.subpixel_fit);
  return s.str();
}

void expect_bit_exact(KernelChoice k, const ImageU8& left, const ImageU8& right,
                      const StereoParams& p, const std::vector<int>& ys,
                      const std::vector<int>& xs, const std::string& what) {
  std::vector<std::vector<std::int16_t>> ref;
  for (int y : ys) ref.push_back(reference::match_row(left, right, y, xs, p));
  const auto got = integer_rows(left, right, p, kernel_set_for(k), ys, xs);
  for (std::size_t r = 0; r < ys.size(); ++r)
    for (std::size_t i = 0; i < xs.size(); ++i)
      ASSERT_EQ(got[r][i], ref[r][i])
          << what << " kernels " << to_string(k) << " row " << ys[r] << " x " << xs[i] << " ("
          << describe(p) << ")";
}

// One instance per kernel set compiled in and runnable here (scalar first).
class MatchReference : public ::testing::TestWithParam<KernelChoice> {};

// ---------------------------------------------------------------- Middlebury

struct Scene {
  std::string name;
  int ndisp;
};

std::vector<Scene> read_scenes() {
  std::ifstream in(test::data_set_dir("middlebury") + "/datasets.tsv");
  std::vector<Scene> scenes;
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::istringstream f(line);
    Scene s;
    int w, h;
    if (f >> s.name >> w >> h >> s.ndisp) scenes.push_back(s);
  }
  return scenes;
}

TEST_P(MatchReference, MiddleburyRowsAreBitExact) {
  TRISTEREO_REQUIRE_MIDDLEBURY();
  const std::vector<Scene> scenes = read_scenes();
  ASSERT_EQ(scenes.size(), 4u) << "datasets.tsv under " << test::data_set_dir("middlebury");
  std::mt19937 rng(2024);
  for (const Scene& scene : scenes) {
    const std::string dir = test::data_set_dir("middlebury") + "/" + scene.name;
    const ImageU8 left = to_gray(read_image_u8(dir + "/left.png"));
    const ImageU8 right = to_gray(read_image_u8(dir + "/right.png"));
    const int w = left.width, h = left.height;
    const std::vector<int> ys = {0, 1, h / 2, h - 1,
                                 std::uniform_int_distribution<int>(2, h - 3)(rng)};
    std::vector<int> every3, all;
    for (int x = 0; x < w; ++x) {
      all.push_back(x);
      if (x % 3 == 0) every3.push_back(x);
    }

    StereoParams box = paper_params();  // AD, 5x5 box, sub-pixel on
    box.num_disp = scene.ndisp;
    StereoParams adaptive = box;
    adaptive.cost.weights = Weights::kAdaptive;
    adaptive.cost.window_w = adaptive.cost.window_h = 15;
    StereoParams random = box;
    random.d_min = std::uniform_int_distribution<int>(-5, 5)(rng);
    random.cost.window_w = 2 * std::uniform_int_distribution<int>(0, 10)(rng) + 1;
    random.cost.window_h = 2 * std::uniform_int_distribution<int>(0, 10)(rng) + 1;
    random.cost.truncation = std::uniform_int_distribution<int>(1, 255)(rng);
    random.cost.weights = Weights::kAdaptive;
    random.cost.asw_gamma_color = std::uniform_int_distribution<int>(1, 60)(rng);
    random.cost.asw_gamma_proximity = std::uniform_int_distribution<int>(1, 300)(rng);
    random.dp.lambda_q4 = std::uniform_int_distribution<int>(0, 32000)(rng);
    random.dp.gap = GapPolicy::kInvSquare;
    random.dp.subpixel_fit = SubpixelFit::kEquiangular;
    StereoParams random_box = random;
    random_box.cost.weights = Weights::kBox;
    random_box.dp.gap = GapPolicy::kConstant;
    random_box.dp.subpixel = false;

    StereoParams census = random_box;  // the census costs through the same row DP
    census.cost.kind = CostKind::kCensus;
    census.cost.census_w = 9;
    census.cost.census_h = 7;
    StereoParams ad_census = random_box;
    ad_census.cost.kind = CostKind::kAdCensus;
    ad_census.cost.census_w = 5;
    ad_census.cost.census_h = 3;
    ad_census.cost.ad_weight_q4 = std::uniform_int_distribution<int>(0, kMaxAdWeightQ4)(rng);
    for (const StereoParams& p : {box, adaptive, random, random_box, census, ad_census}) {
      expect_bit_exact(GetParam(), left, right, p, ys, every3, scene.name + " every 3rd pixel");
      expect_bit_exact(GetParam(), left, right, p, ys, all, scene.name + " dense");
    }
  }
}

// ---------------------------------------------------------------- random

TEST_P(MatchReference, RandomImagesAndParametersAreBitExact) {
  std::mt19937 rng(77);
  auto uni = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  for (int trial = 0; trial < 1200; ++trial) {
    const int w = uni(2, 28), h = uni(2, 10);
    StereoParams p = paper_params();
    p.d_min = uni(-5, 5);
    p.num_disp = uni(1, 40);
    p.cost.window_w = 2 * uni(0, 15) + 1;
    p.cost.window_h = 2 * uni(0, 15) + 1;
    p.cost.truncation = uni(1, 255);
    p.cost.weights = uni(0, 1) ? Weights::kAdaptive : Weights::kBox;
    p.cost.asw_gamma_color = uni(1, 1000) > 500 ? uni(1, 1000) : uni(1, 30);
    p.cost.asw_gamma_proximity = uni(1, 4) == 1 ? uni(1, 100000) : uni(1, 100);
    p.dp.lambda_q4 = uni(0, 3) == 0 ? uni(0, 32000) : uni(0, 400);
    const GapPolicy gaps[3] = {GapPolicy::kInvSquare, GapPolicy::kInverse, GapPolicy::kConstant};
    p.dp.gap = gaps[uni(0, 2)];
    p.dp.subpixel = uni(0, 1) == 1;
    p.dp.subpixel_fit = uni(0, 1) == 1 ? SubpixelFit::kEquiangular : SubpixelFit::kParabola;
    if (trial % 3 != 0) {  // the census costs (box-aggregated)
      p.cost.kind = trial % 3 == 1 ? CostKind::kCensus : CostKind::kAdCensus;
      p.cost.weights = Weights::kBox;
      p.cost.census_w = 2 * uni(1, 4) + 1;
      p.cost.census_h = 2 * uni(1, 4) + 1;
      if (p.cost.census_w * p.cost.census_h > 65) p.cost.census_h = 7;
      p.cost.ad_weight_q4 = uni(0, kMaxAdWeightQ4);
    }

    // Textures from flat to noisy, with right = shifted left plus noise
    // sometimes, so both well-matched and ambiguous rows occur.
    ImageU8 left(w, h), right(w, h);
    const int amp = uni(0, 3) == 0 ? 3 : 255;
    const int shift = uni(-6, 6);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) left.at(x, y) = static_cast<std::uint8_t>(uni(0, amp));
    const bool shifted = uni(0, 1) == 1;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const int sx = x + shift;
        right.at(x, y) = shifted && sx >= 0 && sx < w
                             ? static_cast<std::uint8_t>(std::min(255, left.at(sx, y) + uni(0, 2)))
                             : static_cast<std::uint8_t>(uni(0, amp));
      }
    std::vector<int> xs;
    const int mode = uni(0, 2);
    for (int x = 0; x < w; ++x)
      if (mode == 0 || (mode == 1 && x % 3 == 0) || (mode == 2 && uni(0, 2) == 0)) xs.push_back(x);
    if (xs.empty()) xs.push_back(uni(0, w - 1));
    std::vector<int> ys;
    for (int y = 0; y < h; ++y) ys.push_back(y);
    expect_bit_exact(GetParam(), left, right, p, ys, xs, "trial " + std::to_string(trial));
    if (HasFatalFailure()) return;
  }
}

INSTANTIATE_TEST_SUITE_P(KernelSets, MatchReference, ::testing::ValuesIn(available_kernel_sets()),
                         [](const ::testing::TestParamInfo<KernelChoice>& info) {
                           return std::string(to_string(info.param));
                         });

}  // namespace
}  // namespace tristereo
