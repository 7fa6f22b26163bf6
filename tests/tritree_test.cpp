// Tests of the integer tritree (src/tritree), its fill rule and the PSNR
// threshold: exact known answers and the mesh invariants of docs/model.md
// section 1. Equality with the float reference is in tritree_reference_test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <set>
#include <utility>
#include <vector>

#include "platform/thread_pool.hpp"
#include "src/model/psnr_threshold.hpp"
#include "src/tritree/fill_rule.hpp"
#include "src/tritree/plane_residual.hpp"
#include "src/tritree/tritree.hpp"
#include "src/tritree/tritree_criterion.hpp"
#include "src/tritree/tritree_geometry.hpp"
#include "support/alloc_counter.hpp"
#include "support/scenes.hpp"
#include "tristereo/gray.hpp"
#include "tristereo/status.hpp"
#include "tristereo/synth.hpp"

namespace tristereo {
namespace {

using test::Rng;

ImageView<const std::uint8_t> cview(const ImageU8& img) { return img.view(); }

Mesh build_mesh(const ImageU8& gray, const TritreeParams& params, Tritree* tree_out = nullptr) {
  Tritree local;
  Tritree& tree = tree_out ? *tree_out : local;
  tree.configure(gray.width, gray.height, params);
  Mesh mesh;
  tree.reserve(mesh);
  tree.build(cview(gray), mesh);
  return mesh;
}

// Smooth gradient + noise + a step, all clamped to 0..255.
ImageU8 mixed_image(Rng& rng, int w, int h) {
  ImageU8 img(w, h);
  const int gx = rng.uniform(-6, 6), gy = rng.uniform(-6, 6), noise = rng.uniform(0, 20);
  const int step_x = rng.uniform(0, w), step = rng.uniform(-120, 120);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      int v = 128 + gx * (x - w / 2) + gy * (y - h / 2) + (x >= step_x ? step : 0);
      if (noise > 0) v += rng.uniform(-noise, noise);
      img.at(x, y) = static_cast<std::uint8_t>(std::clamp(v, 0, 255));
    }
  }
  return img;
}

// ------------------------------------------------------------ PSNR threshold

TEST(PsnrThreshold, CommittedStepConstantRegenerates) {
  const long double step = std::pow(10.0L, -0.01L) * 2147483648.0L;
  EXPECT_EQ(static_cast<std::uint64_t>(std::llround(step)), kPsnrStepQ31);
}

TEST(PsnrThreshold, MatchesPowForEveryTenthDb) {
  // The integer result is the definition; this only checks it is the rounded
  // real value up to the Q31 power's tiny error.
  for (int d = kMinPsnrDeciDb; d <= kMaxPsnrDeciDb; ++d) {
    const long double exact = 256.0L * 65025.0L * std::pow(10.0L, -d / 100.0L);
    const long double got = static_cast<long double>(mse_threshold_q8(d));
    EXPECT_LE(std::fabs(got - exact), 0.5L + 1e-6L * exact) << "psnr_deci_db " << d;
  }
  EXPECT_EQ(mse_threshold_q8(0), 16646400u);   // 0 dB: full scale, exactly
  EXPECT_EQ(mse_threshold_q8(400), 1665u);     // 1664.64
  EXPECT_EQ(mse_threshold_q8(700), 2u);        // 1.66
}

// ------------------------------------------------------------ fill rule

TEST(FillRule, SpansEqualBruteForceOnRandomTriangles) {
  Rng rng(11);
  int checked = 0;
  for (int it = 0; it < 20000; ++it) {
    const int w = rng.uniform(2, 24), h = rng.uniform(2, 24);
    Vertex v[3];
    for (Vertex& p : v) p = Vertex{rng.uniform(0, w - 1), rng.uniform(0, h - 1)};
    const std::int64_t a2 = area2_of(v[0], v[1], v[2]);
    if (a2 == 0) continue;
    if (a2 < 0) std::swap(v[1], v[2]);
    std::vector<char> by_span(static_cast<std::size_t>(w) * h, 0);
    int last_y = -1;
    for_each_owned_span(v[0], v[1], v[2], w, h, [&](int y, int x0, int x1) {
      ASSERT_GT(y, last_y);
      ASSERT_LT(x0, x1);
      ASSERT_GE(x0, 0);
      ASSERT_LE(x1, w);
      last_y = y;
      for (int x = x0; x < x1; ++x) by_span[static_cast<std::size_t>(y) * w + x] = 1;
    });
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        ASSERT_EQ(by_span[static_cast<std::size_t>(y) * w + x] != 0,
                  owns_pixel(v[0], v[1], v[2], x, y, w, h))
            << "triangle (" << v[0].x << "," << v[0].y << ") (" << v[1].x << "," << v[1].y
            << ") (" << v[2].x << "," << v[2].y << ") pixel " << x << "," << y;
      }
    }
    ++checked;
  }
  EXPECT_GT(checked, 15000);
}

TEST(FillRule, TwoRootsOfA2x2ImageShareItsPixels) {
  // Roots (0,0),(1,0),(1,1) (above the diagonal, y < x) and (0,0),(1,1),(0,1).
  // The diagonal pixels are decided by the nudge: (0,0) moves to (e, e^2),
  // above the diagonal; (1,1) moves to (1-e, 1-e^2), below it.
  const Vertex a{0, 0}, b{1, 0}, c{1, 1}, d{0, 1};
  EXPECT_TRUE(owns_pixel(a, b, c, 0, 0, 2, 2));
  EXPECT_TRUE(owns_pixel(a, b, c, 1, 0, 2, 2));
  EXPECT_FALSE(owns_pixel(a, b, c, 1, 1, 2, 2));
  EXPECT_FALSE(owns_pixel(a, b, c, 0, 1, 2, 2));
  EXPECT_FALSE(owns_pixel(a, c, d, 0, 0, 2, 2));
  EXPECT_FALSE(owns_pixel(a, c, d, 1, 0, 2, 2));
  EXPECT_TRUE(owns_pixel(a, c, d, 1, 1, 2, 2));
  EXPECT_TRUE(owns_pixel(a, c, d, 0, 1, 2, 2));
}

// ------------------------------------------------------------ residual kernel

TEST(PlaneResidual, SpanSumMatchesDirectFormula) {
  const std::uint8_t row[8] = {0, 10, 20, 255, 7, 3, 100, 200};
  // r(x) = r0 + n_x (x - 2) + area2 row[x] for x in [2, 7).
  const std::int64_t r0 = -300, n_x = 13, area2 = 6;
  std::uint64_t expected = 0;
  for (int x = 2; x < 7; ++x) {
    const std::int64_t r = r0 + n_x * (x - 2) + area2 * row[x];
    expected += static_cast<std::uint64_t>(r * r);
  }
  EXPECT_EQ(plane_residual_sse_span_scalar(row, 2, 7, r0, n_x, area2), expected);
  EXPECT_EQ(plane_residual_sse_span_scalar(row, 3, 3, r0, n_x, area2), 0u);
  // One pixel: (-300 + 6 * 255)^2 = 1230^2.
  EXPECT_EQ(plane_residual_sse_span_scalar(row, 3, 4, r0, n_x, area2), 1512900u);
}

// ------------------------------------------------------------ split criterion

// The criterion straight from docs/model.md: every pixel tested with
// owns_pixel(), the full SSE, no early exit.
bool wants_split_brute_force(const ImageU8& img, Vertex a, Vertex b, Vertex c, int max_area_px2,
                             std::uint64_t mse_q8) {
  const std::int64_t area2 = area2_of(a, b, c);
  if (area2 > 2 * std::int64_t{max_area_px2}) return true;
  const std::int64_t ia = img.at(a.x, a.y), ib = img.at(b.x, b.y), ic = img.at(c.x, c.y);
  const std::int64_t n_x = (b.y - a.y) * (ic - ia) - (ib - ia) * (c.y - a.y);
  const std::int64_t n_y = (ib - ia) * (c.x - a.x) - (b.x - a.x) * (ic - ia);
  std::uint64_t sse = 0, n_px = 0;
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      if (!owns_pixel(a, b, c, x, y, img.width, img.height)) continue;
      const std::int64_t r = n_x * (x - a.x) + n_y * (y - a.y) + area2 * (img.at(x, y) - ia);
      sse += static_cast<std::uint64_t>(r * r);
      ++n_px;
    }
  }
  return sse * 256 > mse_q8 * n_px * static_cast<std::uint64_t>(area2 * area2);
}

TEST(Criterion, EqualsBruteForceOnRandomTriangles) {
  // The production criterion walks the spans once and stops early against a
  // bound on the pixel count; its answer must still be the model's.
  Rng rng(21);
  int splits = 0, keeps = 0;
  for (int it = 0; it < 6000; ++it) {
    const int w = rng.uniform(2, 40), h = rng.uniform(2, 40);
    const ImageU8 img = mixed_image(rng, w, h);
    Vertex v[3];
    for (Vertex& p : v) p = Vertex{rng.uniform(0, w - 1), rng.uniform(0, h - 1)};
    const std::int64_t a2 = area2_of(v[0], v[1], v[2]);
    if (a2 == 0) continue;
    if (a2 < 0) std::swap(v[1], v[2]);
    const int max_area = rng.uniform(1, 400);
    const std::uint64_t mse_q8 = mse_threshold_q8(rng.uniform(kMinPsnrDeciDb, kMaxPsnrDeciDb));
    const bool expected = wants_split_brute_force(img, v[0], v[1], v[2], max_area, mse_q8);
    ASSERT_EQ(tritree_wants_split(cview(img), v[0], v[1], v[2], max_area, mse_q8), expected)
        << "triangle (" << v[0].x << "," << v[0].y << ") (" << v[1].x << "," << v[1].y << ") ("
        << v[2].x << "," << v[2].y << ") in " << w << "x" << h << " max_area " << max_area
        << " mse_q8 " << mse_q8;
    (expected ? splits : keeps) += 1;
  }
  // Both answers occur often, so the comparison covers both branches.
  EXPECT_GT(splits, 1000);
  EXPECT_GT(keeps, 1000);
}

// ------------------------------------------------------------ golden meshes

TEST(Tritree, Golden3x3ConstantHandDerived) {
  // Derived by hand from docs/model.md: both roots have area2 4 > 2 * A_max = 2
  // and share their longest edge, the diagonal (len2 8); they split as a pair
  // at M = (1,1), and both wanted to: 2 criterion splits, 0 forced. The four
  // children have area2 2 and the image is constant (SSE 0), so refinement stops.
  ImageU8 img(3, 3, 1, 77);
  TritreeParams params;
  params.max_area_px2 = 1;
  const Mesh m = build_mesh(img, params);
  const std::vector<Vertex> vertices = {{0, 0}, {2, 0}, {1, 1}, {0, 2}, {2, 2}};
  const std::vector<Triangle> triangles = {{0, 1, 2}, {0, 2, 3}, {1, 4, 2}, {2, 4, 3}};
  EXPECT_EQ(m.vertices, vertices);
  EXPECT_EQ(m.triangles, triangles);
  EXPECT_EQ(m.row_start, (std::vector<std::int32_t>{0, 2, 3, 5}));
  EXPECT_EQ(m.criterion_splits, 2);
  EXPECT_EQ(m.forced_splits, 0);
}

TEST(Tritree, Golden9x7Step) {
  // Left of x = 5 a vertical ramp 20 + 10 y, right of it 200; 40 dB, A_max 12.
  // Arrays produced by reference::build_tritree (src/reference) and checked
  // here against the integer path; the invariant tests below cover them too.
  ImageU8 img(9, 7);
  for (int y = 0; y < 7; ++y) {
    for (int x = 0; x < 9; ++x) img.at(x, y) = static_cast<std::uint8_t>(x >= 5 ? 200 : 20 + 10 * y);
  }
  TritreeParams params;
  params.psnr_deci_db = 400;
  params.max_area_px2 = 12;
  const Mesh m = build_mesh(img, params);
  const std::vector<Vertex> vertices = {
      {0, 0}, {4, 0}, {6, 0}, {8, 0}, {2, 1}, {4, 1}, {6, 1}, {5, 2}, {0, 3}, {4, 3},
      {6, 3}, {8, 3}, {2, 4}, {4, 4}, {6, 4}, {5, 5}, {0, 6}, {4, 6}, {6, 6}, {8, 6}};
  const std::vector<Triangle> triangles = {
      {0, 1, 4},    {0, 4, 8},    {1, 2, 6},    {1, 5, 4},    {1, 6, 5},    {2, 3, 6},
      {3, 11, 6},   {4, 5, 9},    {4, 9, 8},    {5, 6, 7},    {5, 7, 9},    {6, 10, 7},
      {6, 11, 10},  {7, 10, 9},   {8, 9, 12},   {8, 12, 16},  {9, 10, 14},  {9, 13, 12},
      {9, 14, 13},  {10, 11, 14}, {11, 19, 14}, {12, 13, 17}, {12, 17, 16}, {13, 14, 15},
      {13, 15, 17}, {14, 18, 15}, {14, 19, 18}, {15, 18, 17}};
  EXPECT_EQ(m.vertices, vertices);
  EXPECT_EQ(m.triangles, triangles);
  EXPECT_EQ(m.row_start, (std::vector<std::int32_t>{0, 4, 7, 8, 12, 15, 16, 20}));
  EXPECT_EQ(m.criterion_splits, 19);
  EXPECT_EQ(m.forced_splits, 7);
}

// ------------------------------------------------------------ invariants

// Checks every structural property of docs/model.md section 1 on `m`.
void expect_valid_mesh(const ImageU8& gray, const TritreeParams& params, const Mesh& m,
                       const std::vector<std::array<Vertex, 3>>& blocked) {
  const int w = gray.width, h = gray.height;
  ASSERT_EQ(m.width, w);
  ASSERT_EQ(m.height, h);
  // Vertices strictly in raster order, row index consistent.
  ASSERT_EQ(m.row_start.size(), static_cast<std::size_t>(h) + 1);
  ASSERT_EQ(m.row_start.front(), 0);
  ASSERT_EQ(m.row_start.back(), static_cast<std::int32_t>(m.vertices.size()));
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    const Vertex& v = m.vertices[i];
    ASSERT_TRUE(v.x >= 0 && v.x < w && v.y >= 0 && v.y < h);
    ASSERT_GE(static_cast<std::int32_t>(i), m.row_start[v.y]);
    ASSERT_LT(static_cast<std::int32_t>(i), m.row_start[v.y + 1]);
    if (i > 0) {
      const Vertex& p = m.vertices[i - 1];
      ASSERT_TRUE(p.y < v.y || (p.y == v.y && p.x < v.x));
    }
  }
  std::vector<std::int32_t> grid(static_cast<std::size_t>(w) * h, -1);
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    grid[static_cast<std::size_t>(m.vertices[i].y) * w + m.vertices[i].x] = static_cast<std::int32_t>(i);
  }

  // Canonical triangles, positive orientation, areas tile the rectangle.
  std::int64_t area_sum = 0;
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    const Triangle& t = m.triangles[i];
    ASSERT_TRUE(t[0] < t[1] && t[0] < t[2]);
    if (i > 0) {
      ASSERT_LT(m.triangles[i - 1], t);
    }
    const std::int64_t a2 = area2_of(m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]);
    ASSERT_GT(a2, 0);
    area_sum += a2;
  }
  EXPECT_EQ(area_sum, 2 * std::int64_t{w - 1} * (h - 1));

  // Every pixel owned by exactly one triangle.
  std::vector<int> owners(static_cast<std::size_t>(w) * h, 0);
  for (const Triangle& t : m.triangles) {
    for_each_owned_span(m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]], w, h,
                        [&](int y, int x0, int x1) {
                          for (int x = x0; x < x1; ++x) ++owners[static_cast<std::size_t>(y) * w + x];
                        });
  }
  for (std::size_t p = 0; p < owners.size(); ++p) ASSERT_EQ(owners[p], 1) << "pixel " << p;

  // Conforming: no vertex on an edge (other than its endpoints) or inside a
  // triangle. Lattice points of edge AB are A + k (AB / g), g = gcd.
  for (const Triangle& t : m.triangles) {
    for (int e = 0; e < 3; ++e) {
      const Vertex a = m.vertices[t[e]], b = m.vertices[t[(e + 1) % 3]];
      const int dx = b.x - a.x, dy = b.y - a.y;
      const int g = std::gcd(std::abs(dx), std::abs(dy));
      for (int k = 1; k < g; ++k) {
        const int x = a.x + k * dx / g, y = a.y + k * dy / g;
        ASSERT_EQ(grid[static_cast<std::size_t>(y) * w + x], -1)
            << "hanging vertex (" << x << "," << y << ") on edge (" << a.x << "," << a.y
            << ")-(" << b.x << "," << b.y << ")";
      }
    }
    const Vertex a = m.vertices[t[0]], b = m.vertices[t[1]], c = m.vertices[t[2]];
    for (int y = std::min({a.y, b.y, c.y}); y <= std::max({a.y, b.y, c.y}); ++y) {
      for (int x = std::min({a.x, b.x, c.x}); x <= std::max({a.x, b.x, c.x}); ++x) {
        const Vertex p{x, y};
        if (area2_of(a, b, p) > 0 && area2_of(b, c, p) > 0 && area2_of(c, a, p) > 0) {
          ASSERT_EQ(grid[static_cast<std::size_t>(y) * w + x], -1) << "vertex inside a triangle";
        }
      }
    }
  }

  // Every leaf passes the criterion, or its own bisection is invalid, or it
  // was blocked.
  std::set<std::array<std::int64_t, 3>> blocked_keys;
  for (const auto& b : blocked) {
    std::array<std::int64_t, 3> k = {vertex_key(b[0]), vertex_key(b[1]), vertex_key(b[2])};
    std::sort(k.begin(), k.end());
    blocked_keys.insert(k);
  }
  const std::uint64_t mse_q8 = mse_threshold_q8(params.psnr_deci_db);
  std::size_t blocked_seen = 0;
  for (const Triangle& t : m.triangles) {
    Vertex v[3] = {m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]};
    std::array<std::int64_t, 3> k = {vertex_key(v[0]), vertex_key(v[1]), vertex_key(v[2])};
    std::sort(k.begin(), k.end());
    const bool is_blocked = blocked_keys.count(k) != 0;
    blocked_seen += is_blocked;
    const int l = longest_edge_index(v);
    const Vertex a = v[l], b = v[(l + 1) % 3], c = v[(l + 2) % 3];
    const bool own_valid = half_bisection_valid(a, b, c, snapped_midpoint(a, b));
    const bool wants = tritree_wants_split(cview(gray), a, b, c, params.max_area_px2, mse_q8);
    EXPECT_TRUE(!wants || !own_valid || is_blocked);
  }
  EXPECT_EQ(blocked_seen, blocked.size());  // blocked triangles are leaves of the mesh
}

TEST(Tritree, InvariantsOnRandomImages) {
  Rng rng(2024);
  for (int it = 0; it < 300; ++it) {
    const int w = rng.uniform(2, 48), h = rng.uniform(2, 48);
    const ImageU8 img = mixed_image(rng, w, h);
    TritreeParams params;
    params.psnr_deci_db = rng.uniform(kMinPsnrDeciDb, kMaxPsnrDeciDb);
    params.max_area_px2 = rng.uniform(1, 64);
    Tritree tree;
    const Mesh m = build_mesh(img, params, &tree);
    SCOPED_TRACE(::testing::Message() << "image " << it << " " << w << "x" << h);
    expect_valid_mesh(img, params, m, tree.blocked_leaves());
    if (HasFatalFailure()) return;
  }
}

TEST(Tritree, InvariantsOnMiddlebury) {
  TRISTEREO_REQUIRE_MIDDLEBURY();
  for (const std::string& name : test::middlebury_names()) {
    const ImageU8 gray = to_gray(test::load_middlebury(name).left);
    const TritreeParams params;  // defaults: 40 dB, 100 px^2
    Tritree tree;
    const Mesh m = build_mesh(gray, params, &tree);
    SCOPED_TRACE(name);
    expect_valid_mesh(gray, params, m, tree.blocked_leaves());
    EXPECT_GT(m.vertices.size(), 1000u);  // a textured scene is refined well below A_max
  }
}

TEST(Tritree, DeterministicAndReusable) {
  Rng rng(7);
  const ImageU8 a = mixed_image(rng, 61, 37);
  const ImageU8 b = mixed_image(rng, 20, 50);
  TritreeParams params;
  params.max_area_px2 = 20;
  Tritree tree;
  tree.configure(64, 64, params);
  Mesh m1, m2, m3;
  tree.reserve(m1);
  tree.build(cview(a), m1);
  tree.build(cview(b), m2);  // a different size in between
  tree.build(cview(a), m3);
  EXPECT_EQ(m1, m3);
  EXPECT_EQ(m1, build_mesh(a, params));
  EXPECT_EQ(m2, build_mesh(b, params));
  EXPECT_FALSE(m1 == m2);
}

TEST(Tritree, BuildDoesNotAllocate) {
  Rng rng(12);
  const ImageU8 small = mixed_image(rng, 30, 20);
  const ImageU8 large = mixed_image(rng, 90, 70);
  TritreeParams params;
  params.max_area_px2 = 4;  // deep refinement: many rounds and forced splits
  Tritree tree;
  tree.configure(90, 70, params);
  Mesh mesh;
  tree.reserve(mesh);
  tree.build(cview(small), mesh);  // warm-up
  test::start_counting_allocations();
  tree.build(cview(large), mesh);
  tree.build(cview(small), mesh);
  EXPECT_EQ(test::stop_counting_allocations(), 0);
  EXPECT_GT(mesh.vertices.size(), 50u);
}

// A started pool (unpinned) and a tree configured and reserved for it: the
// setup of every pooled-build test.
struct PooledTree {
  PooledTree(int workers, int max_width, int max_height, const TritreeParams& params) {
    pool.start(workers, {}, /*pin=*/false);
    tree.configure(max_width, max_height, params);
    tree.reserve(mesh);
  }
  const Mesh& build(const ImageU8& img) {
    tree.build(cview(img), mesh, &pool);
    return mesh;
  }
  ThreadPool pool;
  Tritree tree;
  Mesh mesh;
};

TEST(Tritree, BuildTimesCoverRoundsIdleAndOutput) {
  SynthParams sp;
  sp.width = 320;
  sp.height = 240;
  const ImageU8 img = make_synthetic_scene(sp).left;
  PooledTree one(1, sp.width, sp.height, TritreeParams{});
  PooledTree two(2, sp.width, sp.height, TritreeParams{});
  one.build(img);
  two.build(img);
  for (const PooledTree* p : {&one, &two}) {
    const Tritree::BuildTimes& t = p->tree.build_times();
    EXPECT_GT(t.rounds_ns, 0);
    EXPECT_GT(t.output_ns, 0);
    // Each worker's busy time lies inside its round's wall time.
    EXPECT_GE(t.round_idle_ns, 0);
  }
  // One worker: no parallel round, so no idle time is counted.
  EXPECT_EQ(one.tree.build_times().round_idle_ns, 0);
  EXPECT_GT(two.tree.regions(), 1);
}

TEST(Tritree, IdenticalForAnyThreadCount) {
  // The criterion runs in parallel chunks; the mesh must not depend on the
  // worker count (1, 2, 3, 8 workers, unpinned) nor differ from a pool-less build.
  TRISTEREO_REQUIRE_MIDDLEBURY();
  std::vector<ImageU8> images;
  SynthParams sp;
  sp.width = 320;
  sp.height = 240;
  images.push_back(make_synthetic_scene(sp).left);
  for (const std::string& name : test::middlebury_names()) {
    images.push_back(to_gray(test::load_middlebury(name).left));
  }
  Rng rng(31);
  for (int i = 0; i < 4; ++i) images.push_back(mixed_image(rng, rng.uniform(40, 200), rng.uniform(40, 200)));
  const TritreeParams params;
  std::vector<Mesh> serial;
  for (const ImageU8& img : images) serial.push_back(build_mesh(img, params));

  for (const int workers : {1, 2, 3, 8}) {
    PooledTree pooled(workers, 450, 383, params);
    ASSERT_EQ(pooled.pool.size(), workers);
    for (std::size_t i = 0; i < images.size(); ++i) {
      ASSERT_EQ(pooled.build(images[i]), serial[i]) << workers << " workers, image " << i;
    }
  }
  EXPECT_GT(serial[0].triangles.size(), 5000u);  // big enough to run the parallel path
}

TEST(Tritree, PoolBuildOfTinyAndThinImagesMatchesSerial) {
  // The pooled finish cuts rows, node slots and vertex ids into one band per
  // worker (at most 16): with more workers than rows or triangles many bands
  // are empty, and 20 workers exceed the band cap. Fine refinement
  // (A_max = 1) also makes every round after the first few tiny.
  Rng rng(77);
  std::vector<ImageU8> images;
  for (const auto& size : {std::pair<int, int>{2, 2}, {3, 2}, {2, 41}, {57, 3}, {33, 29}}) {
    images.push_back(mixed_image(rng, size.first, size.second));
  }
  TritreeParams params;
  params.max_area_px2 = 1;
  params.psnr_deci_db = kMaxPsnrDeciDb;
  for (const int workers : {2, 8, 20}) {
    PooledTree pooled(workers, 64, 64, params);
    for (std::size_t i = 0; i < images.size(); ++i) {
      const Mesh& mesh = pooled.build(images[i]);
      const Mesh serial = build_mesh(images[i], params);
      ASSERT_EQ(mesh, serial) << workers << " workers, image " << i;
      EXPECT_EQ(mesh.row_start.back(), static_cast<std::int32_t>(mesh.vertices.size()));
    }
  }
}

TEST(Tritree, BuildWithPoolDoesNotAllocate) {
  SynthParams sp;
  sp.width = 200;
  sp.height = 150;
  const ImageU8 img = make_synthetic_scene(sp).left;
  PooledTree pooled(3, 200, 150, TritreeParams{});
  pooled.build(img);  // warm-up
  test::start_counting_allocations();
  pooled.build(img);
  EXPECT_EQ(test::stop_counting_allocations(), 0);
  EXPECT_GT(pooled.mesh.triangles.size(), 1000u);
}

TEST(Tritree, StrideMatchesPackedBuild) {
  Rng rng(8);
  const ImageU8 img = mixed_image(rng, 33, 21);
  TritreeParams params;
  params.max_area_px2 = 10;
  // Same pixels, rows padded to 40 bytes.
  std::vector<std::uint8_t> padded(40 * 21, 0xAB);
  for (int y = 0; y < 21; ++y) std::copy(img.row(y), img.row(y) + 33, padded.data() + 40 * y);
  const ImageView<const std::uint8_t> view{padded.data(), 33, 21, 1, 40};
  Tritree tree;
  tree.configure(33, 21, params);
  Mesh strided;
  tree.build(view, strided);
  EXPECT_EQ(strided, build_mesh(img, params));
  EXPECT_GT(tree.rounds(), 3);
}

TEST(Tritree, ManyRegionsDeferCrossingPropagationsAndMatchSerial) {
  // Fine meshes cut into up to 64 stripes: many propagations cross a stripe
  // border and are finished by the merge tree over the regions (12 and 20
  // regions give groups with a single half). The mesh and the split counts
  // must equal the single-region build's.
  Rng rng(41);
  TritreeParams params;
  params.max_area_px2 = 4;
  params.psnr_deci_db = 450;
  std::vector<ImageU8> images;
  for (int i = 0; i < 6; ++i) images.push_back(mixed_image(rng, rng.uniform(90, 200), rng.uniform(60, 160)));
  for (const int workers : {2, 3, 5, 16}) {
    PooledTree pooled(workers, 200, 160, params);
    std::int64_t deferred = 0;
    for (std::size_t i = 0; i < images.size(); ++i) {
      ASSERT_EQ(pooled.build(images[i]), build_mesh(images[i], params))
          << workers << " workers, image " << i;
      EXPECT_EQ(pooled.tree.regions(), std::min(Tritree::kRegionsPerWorker * workers, Tritree::kMaxRegions));
      deferred += pooled.tree.deferred_propagations();
    }
    EXPECT_GT(deferred, 0) << workers << " workers: no propagation was ever deferred";
  }
}

TEST(Tritree, RegionOutOfSlotsFallsBackToOneRegion) {
  // The midpoint snap moves slivers of area between the two triangles of a
  // pair, so a region's leaves can outgrow its stripe's area bound. Without
  // spare slots, image 31 of this sequence (115x106, 3 workers, 24 regions)
  // runs a region out of slots: the build must start over on one region and
  // still give the serial mesh. With the default spare none of them does.
  const TritreeParams params;
  std::vector<ImageU8> images;
  Rng rng(7);
  for (int i = 0; i < 32; ++i) {
    const int w = rng.uniform(40, 200);
    const int h = rng.uniform(40, 200);  // drawn in order: argument order is unspecified
    images.push_back(mixed_image(rng, w, h));
  }
  PooledTree no_spare(3, 200, 200, params);
  no_spare.tree.limit_spare_slots_for_testing(0);
  PooledTree with_spare(3, 200, 200, params);
  int fallbacks = 0, partitioned = 0;
  for (std::size_t i = 0; i < images.size(); ++i) {
    const Mesh serial = build_mesh(images[i], params);
    ASSERT_EQ(no_spare.build(images[i]), serial) << "image " << i << ", no spare slots";
    fallbacks += no_spare.tree.fell_back_to_one_region() ? 1 : 0;
    ASSERT_EQ(with_spare.build(images[i]), serial) << "image " << i;
    EXPECT_FALSE(with_spare.tree.fell_back_to_one_region()) << "image " << i;
    partitioned += with_spare.tree.regions() == 3 * Tritree::kRegionsPerWorker ? 1 : 0;
  }
  EXPECT_GE(fallbacks, 1);
  EXPECT_GE(partitioned, 16);  // the small images never reach 64 leaves per region
}

TEST(Tritree, CountsCriterionAndForcedSplits) {
  // Every split is one of the two kinds, and each split adds one triangle.
  Rng rng(9);
  const ImageU8 img = mixed_image(rng, 40, 30);
  TritreeParams params;
  params.max_area_px2 = 8;
  const Mesh m = build_mesh(img, params);
  EXPECT_EQ(static_cast<std::int64_t>(m.triangles.size()), 2 + m.criterion_splits + m.forced_splits);
  EXPECT_GT(m.forced_splits, 0);
}

// ------------------------------------------------------------ bad input

TEST(Tritree, RejectsBadConfiguration) {
  Tritree tree;
  TritreeParams ok;
  EXPECT_THROW(tree.configure(1, 10, ok), Error);
  EXPECT_THROW(tree.configure(10, kMaxImageSide + 1, ok), Error);
  TritreeParams bad = ok;
  bad.max_area_px2 = 0;
  EXPECT_THROW(tree.configure(10, 10, bad), Error);
  bad.max_area_px2 = kMaxAreaLimitPx2 + 1;
  EXPECT_THROW(tree.configure(10, 10, bad), Error);
  bad = ok;
  bad.psnr_deci_db = kMinPsnrDeciDb - 1;
  EXPECT_THROW(tree.configure(10, 10, bad), Error);
  bad.psnr_deci_db = kMaxPsnrDeciDb + 1;
  try {
    tree.configure(10, 10, bad);
    FAIL() << "no throw";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(e.what()).find("701"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(tree.configured());
}

TEST(Tritree, RejectsBadImagesWithoutTouchingTheMesh) {
  Tritree tree;
  const ImageU8 img(8, 8, 1, 3);
  Mesh mesh;
  EXPECT_THROW(tree.build(cview(img), mesh), Error);  // not configured
  tree.configure(16, 16, TritreeParams{});
  Mesh before;
  before.width = 123;
  before.vertices = {{1, 2}};
  mesh = before;
  ImageView<const std::uint8_t> v = cview(img);
  auto expect_rejected = [&](ImageView<const std::uint8_t> bad) {
    EXPECT_THROW(tree.build(bad, mesh), Error);
    EXPECT_EQ(mesh, before);
  };
  ImageView<const std::uint8_t> bad = v;
  bad.data = nullptr;
  expect_rejected(bad);
  bad = v;
  bad.width = 1;
  expect_rejected(bad);
  bad = v;
  bad.height = 1;
  expect_rejected(bad);
  const ImageU8 big(17, 8, 1, 0);
  expect_rejected(cview(big));
  bad = v;
  bad.channels = 3;
  expect_rejected(bad);
  bad = v;
  bad.stride_bytes = 7;
  expect_rejected(bad);
  tree.build(v, mesh);  // still usable afterwards
  EXPECT_EQ(mesh.vertices.size(), 4u);  // constant 8x8, roots of 24.5 px^2: no split
}

}  // namespace
}  // namespace tristereo

