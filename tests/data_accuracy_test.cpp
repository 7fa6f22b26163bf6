// Accuracy of the default model on every scene of ../shared/data, scored as the
// data README scores the peers (v2: bad > 1 px on nonocc; 2014 and ETH3D: bad >
// 2 px; KITTI: D1; every known-GT pixel, invalid counts as bad). The output is
// bit-exact everywhere, so each limit is the value measured when the defaults
// were chosen (docs/tuning.md, scripts/tune.py) plus 0.3 points: a regression
// fails. Beside the limits, issue #14's targets, checked as stated.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "support/data.hpp"
#include "tristereo/eval.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/io.hpp"
#include "tristereo/mesh.hpp"
#include "tristereo/params.hpp"
#include "tristereo/pipeline.hpp"

namespace tristereo {
namespace {

// Measured with the defaults (scripts/tune.py, row "defaults"), + 0.3.
const std::map<std::string, double> kMeasured = {
    // TUNED_LIMITS_BEGIN
    {"eth3d/playground", 2.40},  // 2.10
    {"kitti2015/000000", 5.27},  // 4.97
    {"kitti2015/000001", 3.94},  // 3.64
    {"middlebury/cones", 3.45},  // 3.15
    {"middlebury/teddy", 6.41},  // 6.11
    {"middlebury/tsukuba", 5.22},  // 4.92
    {"middlebury/venus", 0.88},  // 0.58
    {"middlebury2014/adirondack", 5.90},  // 5.60
    {"middlebury2014/jadeplant", 22.04},  // 21.74
    {"middlebury2014/motorcycle", 8.24},  // 7.94
    {"middlebury2014/motorcyclee", 7.82},  // 7.52
    {"middlebury2014/piano", 21.37},  // 21.07
    {"middlebury2014/pianol", 24.29},  // 23.99
    {"pianol_gap", 3.22},  // |pianol - piano| 2.92
    // TUNED_LIMITS_END
};

StereoOutput run_scene(const test::DataScene& s, const StereoParams& params) {
  PipelineConfig c;
  c.max_width = s.left.width;
  c.max_height = s.left.height;
  c.params = params;
  c.params.num_disp = s.ndisp;
  c.threads = 2;
  c.pin_threads = false;
  Pipeline p;
  p.configure(c);
  return p.process(s.left.view(), s.right.view());
}

double run_and_score(const test::DataScene& s, const StereoParams& params) {
  const StereoOutput out = run_scene(s, params);
  const Image<float> d = disp_q4_to_float(out.disp_q4.view());
  return test::readme_score(s, d.view());
}

TEST(DataAccuracy, DefaultsOnEverySceneOfEverySet) {
  TRISTEREO_REQUIRE_ALL_DATA();
  std::map<std::string, double> score;
  std::map<std::string, double> set_sum;
  std::map<std::string, int> set_n;
  for (const test::DataScene& s : test::load_all_data_scenes()) {
    const std::string id = s.set + "/" + s.name;
    const double v = run_and_score(s, StereoParams{});
    score[s.name] = v;
    set_sum[s.set] += v;
    ++set_n[s.set];
    ASSERT_TRUE(kMeasured.count(id)) << id << " has no measured limit";
    EXPECT_LE(v, kMeasured.at(id)) << id << " (" << test::to_string(s.metric) << ")";
    // No scene worse than OpenCV's StereoSGBM (3-way) on the same data.
    if (!std::isnan(s.peer_sgbm)) {
      EXPECT_LT(v, s.peer_sgbm) << id << " vs SGBM";
    }
    if (s.set == "kitti2015") {
      EXPECT_LE(v, 10.0) << id << ": KITTI D1 target";
    }
  }
  ASSERT_EQ(set_n["middlebury"], 4);
  ASSERT_EQ(set_n["middlebury2014"], 6);
  EXPECT_LE(set_sum["middlebury"] / 4, 5.0) << "v2 mean bad 1 px nonocc target";
  EXPECT_LE(set_sum["middlebury2014"] / 6, 25.0) << "Middlebury 2014 mean bad 2 px target";
  // Issue #40's set targets (met with depth edges, docs/model.md section 4).
  EXPECT_LE(set_sum["middlebury"] / 4, 3.8) << "issue #40: v2 mean bad 1 px nonocc";
  EXPECT_LE(set_sum["middlebury2014"] / 6, 15.0) << "issue #40: Middlebury 2014 mean bad 2 px";
  // Issue #15: fewer samples, but every set's mean within 0.3 points of the
  // defaults before it (leaves down to 1 px^2 at 40 dB; docs/tuning.md).
  const std::map<std::string, double> before_issue_15 = {
      {"middlebury", 4.30}, {"middlebury2014", 19.71}, {"kitti2015", 6.65}, {"eth3d", 2.90}};
  for (const auto& [set, before] : before_issue_15) {
    ASSERT_GT(set_n[set], 0) << set;
    EXPECT_LE(set_sum[set] / set_n[set], before + 0.3) << set << " mean, issue #15's accuracy bound";
  }
  // A right camera with another exposure or lighting stays within 5 points of its twin.
  EXPECT_LE(std::fabs(score["motorcyclee"] - score["motorcycle"]), 5.0);
  EXPECT_LE(std::fabs(score["pianol"] - score["piano"]), 5.0);
  EXPECT_LE(std::fabs(score["pianol"] - score["piano"]), kMeasured.at("pianol_gap"));
}

// Sub-pixel accuracy on KITTI 2015 (issue #40): bad > 1 px and the end-point
// error on every known-GT pixel, measured with scripts/score_all.py. The
// default fit (parabola) against whole disparities (--no-subpixel: 20.53 and
// 28.08 % bad 1 px, EPE 1.038 and 1.136 px) and against the equiangular fit,
// which scores the same on KITTI within 0.1 points: most errors above 0.5 px
// there are whole-pixel errors of the winners (at the measured samples of
// 000000, half the winners are not the whole disparity nearest the ground
// truth), which no fit through three costs corrects (scripts/tune.py's notes).
TEST(DataAccuracy, SubpixelOnKittiBothFrames) {
  TRISTEREO_REQUIRE_DATA("kitti2015");
  struct Measured {
    double bad1_parabola, epe_parabola, bad1_equiangular, bad1_off;
  };
  // With the support prior (the defaults since 2026-12-06) and depth edges
  // (since 2026-12-07); before both: 24.72 / 30.45 % bad 1 px, EPE 1.412 /
  // 1.553 px; with the prior alone 19.12 / 26.60 %, 0.997 / 1.099 px.
  const std::map<std::string, Measured> measured = {{"000000", {18.88, 1.011, 18.95, 20.53}},
                                                    {"000001", {26.42, 1.112, 26.43, 28.08}}};
  for (const test::DataScene& s : test::load_data_set("kitti2015")) {
    ASSERT_TRUE(measured.count(s.name)) << s.name;
    const Measured& m = measured.at(s.name);
    auto score = [&](const StereoParams& p) {
      const Image<float> d = disp_q4_to_float(run_scene(s, p).disp_q4.view());
      return evaluate_disparity(d.view(), s.gt.view(), {});
    };
    StereoParams off;
    off.dp.subpixel = false;
    StereoParams equiangular;
    equiangular.dp.subpixel_fit = SubpixelFit::kEquiangular;
    const BadPixelStats with = score(StereoParams{}), without = score(off), eq = score(equiangular);
    EXPECT_LE(with.bad_1, m.bad1_parabola + 0.3) << s.name;
    EXPECT_LE(with.epe, m.epe_parabola + 0.02) << s.name;
    // The sub-pixel estimate buys 1.65 to 1.66 points of bad 1 px on both frames.
    EXPECT_LE(with.bad_1, without.bad_1 - 1.2) << s.name;
    EXPECT_LT(with.epe, without.epe) << s.name;
    EXPECT_LE(eq.bad_1, m.bad1_equiangular + 0.3) << s.name;
    EXPECT_LE(eq.bad_1, without.bad_1 - 1.2) << s.name;
  }
}

// Pixel locking (docs/model.md section 3): the parabola through summed census
// costs pulls the measured samples' disparities towards whole pixels; the
// equiangular fit does not. Share of the measured samples at a whole disparity
// (disp_q4 % 16 == 0), measured by this test (its properties): parabola
// 12.2 / 13.2 %, equiangular 6.8 / 7.2 % (adirondack / motorcycle); the float
// ground truth of Middlebury 2014 has 6.5 % there (1/16 of them).
TEST(DataAccuracy, EquiangularFitDoesNotLockToWholePixels) {
  TRISTEREO_REQUIRE_DATA("middlebury2014");
  for (const test::DataScene& s : test::load_data_set("middlebury2014")) {
    if (s.name != "adirondack" && s.name != "motorcycle") continue;
    auto whole_share = [&](SubpixelFit fit) {
      StereoParams p;
      p.dp.subpixel_fit = fit;
      const StereoOutput out = run_scene(s, p);
      long measured = 0, whole = 0;
      for (std::size_t i = 0; i < out.vertex_disp_q4.size(); ++i) {
        if (out.vertex_state[i] != static_cast<std::uint8_t>(SampleState::kMeasured)) continue;
        ++measured;
        whole += (out.vertex_disp_q4[i] & (kDispOne - 1)) == 0;
      }
      return measured > 0 ? 100.0 * static_cast<double>(whole) / static_cast<double>(measured) : 100.0;
    };
    const double parabola = whole_share(SubpixelFit::kParabola);
    const double equiangular = whole_share(SubpixelFit::kEquiangular);
    RecordProperty(s.name + "_parabola_whole_pct", std::to_string(parabola));
    RecordProperty(s.name + "_equiangular_whole_pct", std::to_string(equiangular));
    EXPECT_GE(parabola, 11.0) << s.name;
    EXPECT_LE(equiangular, 7.6) << s.name;
  }
}

// The paper's model (--mode paper), the baseline of every comparison, as
// measured with this tritree (docs/tuning.md, row "paper model"); its outputs
// are also pinned bit for bit by the golden digests.
TEST(DataAccuracy, PaperModelAsMeasured) {
  TRISTEREO_REQUIRE_MIDDLEBURY();
  const std::map<std::string, double> paper = {{"tsukuba", 8.3288}, {"venus", 4.1908}, {"teddy", 12.0561}, {"cones", 9.6515}};
  for (const test::DataScene& s : test::load_data_set("middlebury"))
    EXPECT_NEAR(run_and_score(s, paper_params()), paper.at(s.name), 0.0001) << s.name;
}

}  // namespace
}  // namespace tristereo
