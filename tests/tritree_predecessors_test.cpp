// The path predecessors the tritree offers while it emits its leaves
// (src/aggregate/predecessor_offers.hpp) against PathMatcher's scan of the
// finished mesh (docs/model.md 3b): the same table, entry for entry, the same
// reach and the same extent (rows up, pixels ahead per row up), on random
// images and parameters, special sizes (stretched and partial tiles) and
// Middlebury, with 4 and 8 directions and 1-3 workers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <utility>
#include <vector>

#include "platform/thread_pool.hpp"
#include "src/aggregate/path_matcher.hpp"
#include "src/cost/match_context.hpp"
#include "src/kernels/dispatch.hpp"
#include "src/model/psnr_threshold.hpp"
#include "src/tritree/tritree.hpp"
#include "support/scenes.hpp"
#include "tristereo/gray.hpp"

namespace tristereo {
namespace {

using test::Rng;

// Smooth gradient + noise + a step (refines unevenly: every level has leaves).
ImageU8 mixed_image(Rng& rng, int w, int h) {
  ImageU8 img(w, h);
  const int gx = rng.uniform(-6, 6), gy = rng.uniform(-6, 6), noise = rng.uniform(0, 30);
  const int step_x = rng.uniform(0, w), step = rng.uniform(-120, 120);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      int v = 128 + gx * (x - w / 2) + gy * (y - h / 2) + (x >= step_x ? step : 0);
      if (noise > 0) v += rng.uniform(-noise, noise);
      img.at(x, y) = static_cast<std::uint8_t>(std::clamp(v, 0, 255));
    }
  return img;
}

// The mesh of `gray` with the tritree's predecessor table, and the scan's
// table of the same mesh: they must agree.
void expect_same_predecessors(const ImageU8& gray, const StereoParams& p, int workers) {
  const KernelSet& ks = kernel_set_for(KernelChoice::kAuto);
  ThreadPool pool;
  if (workers > 1) pool.start(workers, {}, false);
  Tritree tree;
  tree.configure(gray.width, gray.height, p.tritree);
  Mesh mesh;
  tree.reserve(mesh);
  PathMatcher offered;
  offered.configure(gray.width, gray.height, p, ks, 1);
  PredecessorTable table = offered.predecessor_table();
  tree.build(gray.view(), mesh, workers > 1 ? &pool : nullptr, &table);
  const bool strip = gray.width == 2 || gray.height == 2;
  const SampleLayout s{&mesh, gray.width, gray.height};
  if (strip && mesh.triangles.size() == 2) {
    EXPECT_FALSE(table.filled) << "a 2-pixel strip has no leaves to offer";
    return;
  }
  ASSERT_TRUE(table.filled);

  // The scan: compute_costs finds them on a worker (nothing was supplied).
  PathMatcher scanned;
  MatchContext ctx(gray.width, gray.height, p, ks);
  ctx.begin_frame(gray.view(), gray.view());
  CensusScratch cs;
  cs.resize(gray.width);
  ctx.prepare_right_rows(0, gray.height, &cs);
  scanned.configure(gray.width, gray.height, p, ks, 1);
  ThreadPool one;
  scanned.compute_costs(ctx, s, one);

  int reach = 0, with_pred = 0;
  // The predecessors' extent, as the path passes' plan needs it: rows up,
  // and per pass the pixels ahead along its x order per row up.
  int reach_rows = 1, shear[2] = {0, 0};
  for (int r = 2; r < p.paths.directions; ++r)
    for (int i = 0; i < s.count(); ++i) {
      const int want = scanned.predecessor(s, r, i);
      ASSERT_EQ(offered.predecessor(s, r, i), want)
          << "direction " << r << ", vertex " << i << " at (" << s.x_of(i) << ", " << s.y_of(i) << ")";
      if (want < 0) continue;
      reach = std::max(reach, std::abs(i - want)), ++with_pred;
      const int dy = std::max(1, std::abs(s.y_of(i) - s.y_of(want)));
      const int pass = r % 2;
      const int ahead = pass == 0 ? s.x_of(want) - s.x_of(i) : s.x_of(i) - s.x_of(want);
      reach_rows = std::max(reach_rows, dy);
      if (ahead > 0) shear[pass] = std::max(shear[pass], (ahead + dy - 1) / dy);
    }
  EXPECT_EQ(table.bounds.reach_rows, reach_rows);
  EXPECT_EQ(table.bounds.shear[0], shear[0]);
  EXPECT_EQ(table.bounds.shear[1], shear[1]);
  // The reach bounds every predecessor's id distance, within the rows a row
  // of tiles spans (S + 1 virtual rows: up to S + 2 real ones by a moved last row).
  EXPECT_GE(table.reach, reach);
  const int tile = tree.tile_side();
  int band_bound = 0;
  for (int y = 0; y < gray.height; ++y)
    band_bound = std::max(band_bound, mesh.row_start[static_cast<std::size_t>(std::min(gray.height, y + tile + 2))] -
                                          mesh.row_start[static_cast<std::size_t>(y)] - 1);
  EXPECT_LE(table.reach, band_bound);
  if (s.count() > 16) {
    EXPECT_GT(with_pred, 0);
  }
}

// min_area is clamped to the largest one max_area allows.
StereoParams params_for(int directions, int max_area, int psnr_deci_db, int min_area) {
  StereoParams p;
  p.paths.directions = directions;
  p.tritree.max_area_px2 = max_area;
  p.tritree.psnr_deci_db = psnr_deci_db;
  p.tritree.min_area_px2 = std::min(min_area, largest_min_area_px2(max_area));
  return p;
}

TEST(TritreePredecessors, SameAsTheScanOnRandomImages) {
  Rng rng(2026);
  for (int it = 0; it < 300; ++it) {
    const int w = rng.uniform(2, 90), h = rng.uniform(2, 70);
    const StereoParams p = params_for(rng.uniform(0, 1) ? 8 : 4, rng.uniform(1, 200),
                                      rng.uniform(kMinPsnrDeciDb, kMaxPsnrDeciDb), rng.uniform(1, 4));
    const int workers = rng.uniform(1, 3);
    SCOPED_TRACE(::testing::Message() << "image " << it << " " << w << "x" << h << ", " << p.paths.directions
                                      << " directions, A_max " << p.tritree.max_area_px2 << ", A_min "
                                      << p.tritree.min_area_px2 << ", PSNR "
                                      << p.tritree.psnr_deci_db << " dB/10, " << workers << " workers");
    expect_same_predecessors(mixed_image(rng, w, h), p, workers);
    if (HasFatalFailure()) return;
  }
}

TEST(TritreePredecessors, SameAsTheScanOnSpecialSizes) {
  // 2 x 2, 3 x N, primes, thin, tiles that end exactly, stretched both ways, 4096 wide.
  const std::pair<int, int> sizes[] = {{2, 2},  {3, 3},   {3, 17},  {17, 3},  {5, 7},   {13, 31},  {33, 33},
                                       {34, 34}, {65, 49}, {97, 89}, {127, 4}, {4096, 3}, {4095, 6}, {3, 4096}};
  Rng rng(5);
  for (const auto& size : sizes)
    for (const int area : {1, 7, 100, 1000})
      for (const int directions : {4, 8}) {
        const int min_area = directions == 4 ? 1 : 2;
        SCOPED_TRACE(::testing::Message() << size.first << "x" << size.second << ", A_max " << area << ", "
                                          << directions << " directions, A_min " << min_area);
        expect_same_predecessors(mixed_image(rng, size.first, size.second),
                                 params_for(directions, area, 400, min_area), size.first * size.second > 5000 ? 2 : 1);
        if (HasFatalFailure()) return;
      }
}

TEST(TritreePredecessors, SameAsTheScanOnMiddlebury) {
  TRISTEREO_REQUIRE_MIDDLEBURY();
  for (const std::string& name : test::middlebury_names()) {
    const ImageU8 gray = to_gray(test::load_middlebury(name).left);
    for (const int directions : {4, 8}) {
      SCOPED_TRACE(::testing::Message() << name << ", " << directions << " directions");
      expect_same_predecessors(gray, params_for(directions, 100, directions == 4 ? 400 : 440, directions == 4 ? 1 : 2),
                               2);
      if (HasFatalFailure()) return;
    }
  }
}

// A slot names its predecessor: a key (bit 31 only orders the offers) or the
// scan's id; kNone and the scan's -1 are none.
TEST(TritreePredecessors, SlotsDecodeKeysAndIds) {
  using namespace predecessor_keys;
  EXPECT_EQ(predecessor_of_slot(static_cast<std::int32_t>(kNone)), -1);
  EXPECT_EQ(predecessor_of_slot(-1), -1);
  EXPECT_EQ(predecessor_of_slot(static_cast<std::int32_t>(7u | kWorse)), 7);
  EXPECT_EQ(predecessor_of_slot(7), 7);
  EXPECT_EQ(predecessor_of_slot(0), 0);
  EXPECT_EQ(predecessor_of_slot(static_cast<std::int32_t>(0u | kWorse)), 0);
}

// A table the tritree did not fill (or filled for another mesh) is not used:
// compute_costs scans instead.
TEST(TritreePredecessors, UnfilledTableIsNotUsed) {
  Rng rng(9);
  const ImageU8 a = mixed_image(rng, 40, 30), b = mixed_image(rng, 40, 30);
  const StereoParams p = params_for(4, 30, 400, 2);
  const KernelSet& ks = kernel_set_for(KernelChoice::kAuto);
  Tritree tree;
  tree.configure(40, 30, p.tritree);
  Mesh ma, mb;
  tree.reserve(ma);
  tree.reserve(mb);
  PathMatcher pm;
  pm.configure(40, 30, p, ks, 1);
  PredecessorTable table = pm.predecessor_table();
  tree.build(a.view(), ma, nullptr, &table);
  ASSERT_TRUE(table.filled);
  pm.use_predecessors(&ma, table);
  tree.build(b.view(), mb);  // another mesh; the table still holds a's
  ASSERT_FALSE(ma == mb);
  const SampleLayout s{&mb, 40, 30};
  MatchContext ctx(40, 30, p, ks);
  ctx.begin_frame(b.view(), b.view());
  CensusScratch cs;
  cs.resize(40);
  ctx.prepare_right_rows(0, 30, &cs);
  ThreadPool one;
  pm.compute_costs(ctx, s, one);  // for mb: scans
  PathMatcher scanned;
  scanned.configure(40, 30, p, ks, 1);
  scanned.compute_costs(ctx, s, one);
  for (int r = 2; r < 4; ++r)
    for (int i = 0; i < s.count(); ++i) ASSERT_EQ(pm.predecessor(s, r, i), scanned.predecessor(s, r, i));
}

}  // namespace
}  // namespace tristereo
