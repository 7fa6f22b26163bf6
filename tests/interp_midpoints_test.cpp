// Interpolation by midpoint averages over the tritree's tiles
// (src/interp/interpolate_midpoints.hpp) against the float reference's one
// plane per triangle: random images, sizes (3 x N, primes, stretched sides,
// partial tiles, 4096 wide), areas and thresholds, random disparities over the
// whole Q4 range with invalid vertices, tile rows in any split; and the
// Middlebury meshes.
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

// The pipeline's order: tiles (in two parts, as two workers would take them),
// the stretched leaves, then the triangles that reach an invalid vertex.
ImageS16 by_midpoints(const Tritree& tree, const Mesh& m, const std::vector<std::int16_t>& vd, int split,
                      const KernelSet& ks) {
  ImageS16 out(m.width, m.height, 1, kUnset);
  const TritreeGrid g = tree.grid();
  std::vector<std::int32_t> values(midpoint_band_values(tree.tile_side(), m.width));
  bool invalid = interpolate_midpoint_tiles(g, m, vd.data(), split, g.layout.tiles_y, ks, values.data(), out.view());
  invalid |= interpolate_midpoint_tiles(g, m, vd.data(), 0, split, ks, values.data(), out.view());
  // The tiles read every vertex, so they tell whether one is invalid (the
  // pipeline skips the triangles' pass when none is).
  bool any = false;
  for (const std::int16_t d : vd) any |= d == kInvalidDispQ4;
  EXPECT_EQ(invalid, any);
  interpolate_stretched_leaves(g, m, vd.data(), out.view());
  invalidate_triangles(m, vd.data(), 0, static_cast<int>(m.triangles.size()), out.view());
  return out;
}

void expect_same_as_reference(const Tritree& tree, const Mesh& m, const std::vector<std::int16_t>& vd,
                              int split, const KernelSet& ks, const std::string& what) {
  const ImageS16 ref = reference::interpolate(m, vd);
  const ImageS16 out = by_midpoints(tree, m, vd, split, ks);
  for (int y = 0; y < m.height; ++y)
    for (int x = 0; x < m.width; ++x)
      ASSERT_EQ(out.at(x, y), ref.at(x, y)) << what << " pixel " << x << "," << y;
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
      const ImageU8 img = test::random_image(rng, w, h);
      TritreeParams tp;
      const int areas[] = {1, 2, 7, 16, 100, 300, 1024};
      tp.max_area_px2 = areas[rng.uniform(0, 6)];
      tp.psnr_deci_db = rng.uniform(kMinPsnrDeciDb, kMaxPsnrDeciDb);
      tp.min_area_px2 = rng.uniform(1, largest_min_area_px2(tp.max_area_px2));
      Tritree tree;
      tree.configure(w, h, tp);
      Mesh m;
      tree.build(img.view(), m);
      const std::vector<std::int16_t> vd = random_disparities(rng, m.vertices.size(), rng.uniform(0, 1) * 30);
      const int split = rng.uniform(0, tree.grid().layout.tiles_y);
      expect_same_as_reference(tree, m, vd, split, ks(),
                               std::to_string(w) + "x" + std::to_string(h) + " A_max " +
                                   std::to_string(tp.max_area_px2) + " A_min " + std::to_string(tp.min_area_px2) +
                                   " eps " + std::to_string(tp.psnr_deci_db));
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
                                 scene + " A_max " + std::to_string(area));
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
    const ImageS16 out = by_midpoints(tree, m, vd, 0, ks());
    for (std::int16_t v : out.pixels) ASSERT_EQ(v, 16 * 5);
  }
}

INSTANTIATE_TEST_SUITE_P(Sets, InterpolateMidpoints, ::testing::ValuesIn(test::all_kernel_params()),
                         test::KernelParamName());

}  // namespace
}  // namespace tristereo
