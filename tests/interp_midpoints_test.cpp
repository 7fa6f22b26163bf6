// Interpolation by midpoint averages over the tritree's tiles
// (src/interp/interpolate_midpoints.hpp) against the float reference's one
// plane per triangle: random images, sizes (3 x N, primes, stretched sides,
// partial tiles, 4096 wide), areas and thresholds, random disparities over the
// whole Q4 range with invalid vertices, tile rows in any split; and the
// Middlebury meshes. With the confidence maps too (docs/model.md section 7),
// against the reference's: random vertex confidences, 0 at invalid vertices.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "src/interp/interpolate_midpoints.hpp"
#include "src/kernels/dispatch.hpp"
#include "src/reference/ref_match.hpp"
#include "src/tritree/tritree.hpp"
#include "support/kernel_param.hpp"
#include "support/scenes.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/gray.hpp"

namespace tristereo {
namespace {

constexpr std::int16_t kUnset = 12345;

constexpr std::uint8_t kUnsetConf = 77;

struct Maps {
  ImageS16 disp;
  ImageU8 confidence, state;
};

// The pipeline's order: tiles (in two parts, as two workers would take them),
// the stretched leaves, then the triangles that reach an invalid vertex; with
// vertex confidences (vc not empty), the confidence maps in the same passes.
Maps by_midpoints(const Tritree& tree, const Mesh& m, const std::vector<std::int16_t>& vd, int split,
                  const KernelSet& ks, const std::vector<std::uint8_t>& vc = {}) {
  Maps out{ImageS16(m.width, m.height, 1, kUnset), ImageU8(m.width, m.height, 1, kUnsetConf),
           ImageU8(m.width, m.height, 1, kUnsetConf)};
  const ConfidenceMaps maps{vc.data(), out.confidence.view(), out.state.view()};
  const ConfidenceMaps* conf = vc.empty() ? nullptr : &maps;
  const TritreeGrid g = tree.grid();
  // The values' band and the confidences' bytes, 0x4D where the kernels
  // read and discard.
  std::vector<std::int32_t> values(midpoint_band_values_with_confidence(tree.tile_side(), m.width), 0x4D4D4D4D);
  bool invalid =
      interpolate_midpoint_tiles(g, m, vd.data(), split, g.layout.tiles_y, ks, values.data(), out.disp.view(), conf);
  invalid |= interpolate_midpoint_tiles(g, m, vd.data(), 0, split, ks, values.data(), out.disp.view(), conf);
  // The tiles read every vertex, so they tell whether one is invalid (the
  // pipeline skips the triangles' pass when none is).
  bool any = false;
  for (const std::int16_t d : vd) any |= d == kInvalidDispQ4;
  EXPECT_EQ(invalid, any);
  // The stretched leaves in two parts too, the later one first.
  const std::size_t half = g.stretched_count / 2;
  interpolate_stretched_leaves(g, m, vd.data(), half, g.stretched_count, out.disp.view(), conf);
  interpolate_stretched_leaves(g, m, vd.data(), 0, half, out.disp.view(), conf);
  invalidate_triangles(m, vd.data(), 0, static_cast<int>(m.triangles.size()), out.disp.view(), conf);
  return out;
}

std::uint8_t state_of(std::uint8_t c) { return c == 0 ? 0 : c < kMinMeasuredConfidence ? 1 : 2; }

// Confidence 0 exactly at the invalid vertices, any of 1..255 elsewhere
// (mostly few distinct values, so that ties occur).
std::vector<std::uint8_t> random_confidences(test::Rng& rng, const std::vector<std::int16_t>& vd) {
  std::vector<std::uint8_t> vc(vd.size());
  const bool few = rng.uniform(0, 1) == 0;
  for (std::size_t i = 0; i < vd.size(); ++i)
    vc[i] = vd[i] == kInvalidDispQ4 ? 0 : static_cast<std::uint8_t>(few ? 1 + 127 * rng.uniform(0, 2) : rng.uniform(1, 255));
  return vc;
}

void expect_same_as_reference(const Tritree& tree, const Mesh& m, const std::vector<std::int16_t>& vd,
                              int split, const KernelSet& ks, const std::string& what,
                              const std::vector<std::uint8_t>& vc = {}) {
  const ImageS16 ref = reference::interpolate(m, vd);
  const Maps out = by_midpoints(tree, m, vd, split, ks, vc);
  for (int y = 0; y < m.height; ++y)
    for (int x = 0; x < m.width; ++x)
      ASSERT_EQ(out.disp.at(x, y), ref.at(x, y)) << what << " pixel " << x << "," << y;
  if (vc.empty()) return;
  std::vector<std::uint8_t> vs(vc.size());
  for (std::size_t i = 0; i < vc.size(); ++i) vs[i] = state_of(vc[i]);
  ImageU8 ref_state, ref_conf;
  reference::interpolate_states(m, vs, vc, ref_state, ref_conf);
  for (int y = 0; y < m.height; ++y)
    for (int x = 0; x < m.width; ++x) {
      ASSERT_EQ(out.confidence.at(x, y), ref_conf.at(x, y)) << what << " confidence at " << x << "," << y;
      ASSERT_EQ(out.state.at(x, y), ref_state.at(x, y)) << what << " state at " << x << "," << y;
    }
}

std::vector<std::int16_t> random_disparities(test::Rng& rng, std::size_t n, int invalid_per_mille) {
  std::vector<std::int16_t> vd(n);
  const int span = rng.uniform(0, 2) == 0 ? 200 : 16 * 2047;  // small steps, or the whole range
  for (auto& d : vd)
    d = rng.uniform(0, 999) < invalid_per_mille ? kInvalidDispQ4 : static_cast<std::int16_t>(rng.uniform(-span, span));
  return vd;
}

// Every kernel set's side-2 level (midpoints_row_q4), scalar included.
class InterpolateMidpoints : public ::testing::TestWithParam<KernelChoice> {
 protected:
  void SetUp() override { TRISTEREO_SKIP_UNLESS_RUNNABLE(GetParam()); }
  const KernelSet& ks() const { return kernel_set_for(GetParam()); }
};

TEST_P(InterpolateMidpoints, RandomImagesSizesAndParameters) {
  test::Rng rng(2811);
  const int sizes[][2] = {{3, 3}, {3, 17}, {17, 3}, {4, 4}, {5, 9}, {31, 37}, {33, 33}, {34, 35},
                          {97, 61}, {128, 64}, {129, 65}, {4096, 5}, {5, 4096}};
  int cases = 0;
  for (int round = 0; round < 40; ++round) {
    for (const auto& wh : sizes) {
      const int w = round < 20 ? wh[0] : rng.uniform(3, 150), h = round < 20 ? wh[1] : rng.uniform(3, 150);
      if (round >= 20 && (wh[0] == 4096 || wh[1] == 4096)) continue;
      Tritree tree;
      TritreeParams tp;
      const Mesh m = test::random_mesh(rng, w, h, tree, &tp);
      const std::vector<std::int16_t> vd = random_disparities(rng, m.vertices.size(), rng.uniform(0, 1) * 30);
      const int split = rng.uniform(0, tree.grid().layout.tiles_y);
      // Every other case with the confidence maps.
      const std::vector<std::uint8_t> vc = round % 2 == 0 ? random_confidences(rng, vd) : std::vector<std::uint8_t>{};
      expect_same_as_reference(tree, m, vd, split, ks(),
                               std::to_string(w) + "x" + std::to_string(h) + " A_max " +
                                   std::to_string(tp.max_area_px2) + " A_min " + std::to_string(tp.min_area_px2) +
                                   " eps " + std::to_string(tp.psnr_deci_db) + (vc.empty() ? "" : " with confidence"),
                               vc);
      if (HasFatalFailure()) return;
      ++cases;
    }
  }
  EXPECT_GT(cases, 400);
}

TEST_P(InterpolateMidpoints, MiddleburyMeshes) {
  TRISTEREO_REQUIRE_MIDDLEBURY();
  test::Rng rng(77);
  for (const std::string& scene : test::middlebury_names()) {
    const test::MiddleburyPair p = test::load_middlebury(scene);
    const ImageU8 gray = to_gray(p.left);
    for (int area : {16, 100, 1024}) {
      Tritree tree;
      const Mesh m = test::tritree_mesh(tree, gray, area);
      for (int invalid : {0, 20}) {
        const std::vector<std::int16_t> vd = random_disparities(rng, m.vertices.size(), invalid);
        expect_same_as_reference(tree, m, vd, tree.grid().layout.tiles_y / 2, ks(),
                                 scene + " A_max " + std::to_string(area), random_confidences(rng, vd));
        if (HasFatalFailure()) return;
      }
    }
  }
}

// Every pixel is written: none keeps the marker, on sizes whose sides are
// stretched, partial in tiles, or both.
TEST_P(InterpolateMidpoints, WritesEveryPixel) {
  test::Rng rng(5);
  for (const auto& wh : {std::pair<int, int>{18, 18}, {19, 20}, {20, 19}, {50, 47}, {64, 65}}) {
    const ImageU8 img = test::random_image(rng, wh.first, wh.second);
    Tritree tree;
    tree.configure(wh.first, wh.second, TritreeParams{});
    Mesh m;
    tree.build(img.view(), m);
    const std::vector<std::int16_t> vd(m.vertices.size(), 16 * 5);
    const Maps out = by_midpoints(tree, m, vd, 0, ks(), std::vector<std::uint8_t>(m.vertices.size(), 200));
    for (std::int16_t v : out.disp.pixels) ASSERT_EQ(v, 16 * 5);
    for (std::uint8_t c : out.confidence.pixels) ASSERT_EQ(c, 200);
    for (std::uint8_t st : out.state.pixels) ASSERT_EQ(st, 2);
  }
}

INSTANTIATE_TEST_SUITE_P(Sets, InterpolateMidpoints, ::testing::ValuesIn(test::all_kernel_params()),
                         test::KernelParamName());

}  // namespace
}  // namespace tristereo
