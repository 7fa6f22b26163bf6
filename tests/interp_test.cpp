// Per-triangle plane interpolation (docs/model.md section 4): planes through
// the vertices reproduced exactly, invalid vertices, thread bands, the float
// reference on random conforming meshes, and bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "src/interp/interpolate_planes.hpp"
#include "src/reference/ref_match.hpp"
#include "src/tritree/tritree.hpp"
#include "tristereo/gray.hpp"
#include "tristereo/io.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/status.hpp"
#include "support/data.hpp"
#include "support/scenes.hpp"

namespace tristereo {
namespace {

constexpr std::int16_t kUnset = 12345;  // never produced below (|d| < 4000)

// A conforming mesh of the w x h rectangle: a grid with cuts at `xs` / `ys`
// (including 0 and w-1 / h-1), interior vertices moved by up to `jitter`
// pixels (kept convex), each cell split along a random diagonal.
Mesh grid_mesh(int w, int h, const std::vector<int>& xs, const std::vector<int>& ys, int jitter,
               std::mt19937& rng) {
  Mesh m;
  m.width = w;
  m.height = h;
  const int nx = static_cast<int>(xs.size()), ny = static_cast<int>(ys.size());
  std::vector<Vertex> grid;
  std::uniform_int_distribution<int> j(-jitter, jitter);
  for (int r = 0; r < ny; ++r)
    for (int c = 0; c < nx; ++c) {
      Vertex v{xs[static_cast<std::size_t>(c)], ys[static_cast<std::size_t>(r)]};
      if (r > 0 && r < ny - 1 && c > 0 && c < nx - 1 && jitter > 0) {
        v.x += j(rng);
        v.y += j(rng);
      }
      grid.push_back(v);
    }
  // Ids in raster order (the mesh convention); the grid is re-indexed.
  std::vector<int> order(grid.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const Vertex& va = grid[static_cast<std::size_t>(a)];
    const Vertex& vb = grid[static_cast<std::size_t>(b)];
    return va.y != vb.y ? va.y < vb.y : va.x < vb.x;
  });
  std::vector<int> id(grid.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    id[static_cast<std::size_t>(order[i])] = static_cast<int>(i);
    m.vertices.push_back(grid[static_cast<std::size_t>(order[i])]);
  }
  auto area2 = [&](int a, int b, int c) {
    const Vertex &A = m.vertices[static_cast<std::size_t>(a)], &B = m.vertices[static_cast<std::size_t>(b)],
                 &C = m.vertices[static_cast<std::size_t>(c)];
    return static_cast<long>(B.x - A.x) * (C.y - A.y) - static_cast<long>(B.y - A.y) * (C.x - A.x);
  };
  std::bernoulli_distribution diag(0.5);
  for (int r = 0; r + 1 < ny; ++r)
    for (int c = 0; c + 1 < nx; ++c) {
      const int a = id[static_cast<std::size_t>(r * nx + c)], b = id[static_cast<std::size_t>(r * nx + c + 1)];
      const int d = id[static_cast<std::size_t>((r + 1) * nx + c)], e = id[static_cast<std::size_t>((r + 1) * nx + c + 1)];
      // a b / d e, y down: (a, b, e) and (a, e, d), or (a, b, d) and (b, e, d).
      Triangle t1{a, b, e}, t2{a, e, d};
      if (diag(rng) || area2(a, b, e) <= 0 || area2(a, e, d) <= 0) {
        t1 = {a, b, d};
        t2 = {b, e, d};
      }
      m.triangles.push_back(t1);
      m.triangles.push_back(t2);
    }
  m.row_start.assign(static_cast<std::size_t>(h) + 1, 0);
  for (const Vertex& v : m.vertices) ++m.row_start[static_cast<std::size_t>(v.y) + 1];
  for (int y = 0; y < h; ++y) m.row_start[static_cast<std::size_t>(y) + 1] += m.row_start[static_cast<std::size_t>(y)];
  return m;
}

bool all_positive(const Mesh& m) {
  for (const Triangle& t : m.triangles) {
    const Vertex &A = m.vertices[static_cast<std::size_t>(t[0])], &B = m.vertices[static_cast<std::size_t>(t[1])],
                 &C = m.vertices[static_cast<std::size_t>(t[2])];
    if (static_cast<long>(B.x - A.x) * (C.y - A.y) - static_cast<long>(B.y - A.y) * (C.x - A.x) <= 0) return false;
  }
  return true;
}

ImageS16 interpolate_all(const Mesh& m, const std::vector<std::int16_t>& vd) {
  ImageS16 out(m.width, m.height, 1, kUnset);
  interpolate_triangles(m, vd.data(), 0, static_cast<int>(m.triangles.size()), out.view());
  return out;
}

TEST(Interpolate, PlaneThroughVerticesIsReproducedExactly) {
  std::mt19937 rng(1);
  const int w = 41, h = 29;
  const Mesh m = grid_mesh(w, h, {0, 8, 16, 24, 32, 40}, {0, 8, 16, 28}, 0, rng);
  // Integer plane in Q4: every pixel value is an integer, so no rounding at all.
  std::vector<std::int16_t> vd;
  for (const Vertex& v : m.vertices) vd.push_back(static_cast<std::int16_t>(80 + 3 * v.x - 2 * v.y));
  ImageS16 out = interpolate_all(m, vd);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) ASSERT_EQ(out.at(x, y), 80 + 3 * x - 2 * y) << x << "," << y;

  // Plane (5x + 3y) / 8 - 7: integral at the vertices (all on multiples of 8),
  // fractional in between; every pixel is its exact value rounded half up.
  const Mesh m8 = grid_mesh(w, 25, {0, 8, 16, 24, 32, 40}, {0, 8, 16, 24}, 0, rng);
  vd.clear();
  for (const Vertex& v : m8.vertices) vd.push_back(static_cast<std::int16_t>((5 * v.x + 3 * v.y) / 8 - 7));
  out = interpolate_all(m8, vd);
  for (int y = 0; y < 25; ++y)
    for (int x = 0; x < w; ++x)
      ASSERT_EQ(out.at(x, y), round_div_half_up(5 * x + 3 * y - 56, 8)) << x << "," << y;
}

TEST(Interpolate, SlantedTrianglesAndNegativeDisparities) {
  // A jittered mesh (slanted edges) carrying one plane with negative values.
  std::mt19937 rng(2);
  const int w = 60, h = 45;
  for (int trial = 0; trial < 20; ++trial) {
    const Mesh m = grid_mesh(w, h, {0, 12, 24, 36, 48, 59}, {0, 11, 22, 33, 44}, 4, rng);
    ASSERT_TRUE(all_positive(m));
    // Plane d = -300 + 2 x - 5 y in Q4 (integral), so every pixel is exact.
    std::vector<std::int16_t> vd;
    for (const Vertex& v : m.vertices) vd.push_back(static_cast<std::int16_t>(-300 + 2 * v.x - 5 * v.y));
    const ImageS16 out = interpolate_all(m, vd);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) ASSERT_EQ(out.at(x, y), -300 + 2 * x - 5 * y) << x << "," << y;
  }
}

TEST(Interpolate, InvalidVertexInvalidatesItsTriangles) {
  std::mt19937 rng(3);
  const Mesh m = grid_mesh(21, 21, {0, 10, 20}, {0, 10, 20}, 0, rng);
  std::vector<std::int16_t> vd(m.vertices.size(), 160);
  // Corner (0, 0) is vertex 0; only triangles using it go invalid.
  vd[0] = kInvalidDispQ4;
  const ImageS16 out = interpolate_all(m, vd);
  const ImageS16 ref = reference::interpolate(m, vd);
  EXPECT_EQ(out.pixels, ref.pixels);
  EXPECT_EQ(out.at(0, 0), kInvalidDispQ4);
  EXPECT_EQ(out.at(20, 20), 160);
  EXPECT_EQ(out.at(15, 15), 160);
  int invalid = 0;
  for (std::int16_t v : out.pixels) {
    EXPECT_TRUE(v == kInvalidDispQ4 || v == 160);
    invalid += v == kInvalidDispQ4;
  }
  EXPECT_GT(invalid, 0);
  EXPECT_LT(invalid, 21 * 21 / 2);
}

TEST(Interpolate, EqualsReferenceOnRandomMeshesAndAnyTriangleBands) {
  std::mt19937 rng(4);
  for (int trial = 0; trial < 300; ++trial) {
    const int w = std::uniform_int_distribution<int>(2, 70)(rng);
    const int h = std::uniform_int_distribution<int>(2, 50)(rng);
    auto cuts = [&](int n) {
      std::vector<int> c{0, n - 1};
      const int extra = std::uniform_int_distribution<int>(0, std::min(6, n - 2))(rng);
      for (int i = 0; i < extra; ++i) c.push_back(std::uniform_int_distribution<int>(1, n - 2)(rng));
      std::sort(c.begin(), c.end());
      c.erase(std::unique(c.begin(), c.end()), c.end());
      return c;
    };
    const std::vector<int> xs = cuts(w), ys = cuts(h);
    int min_gap = 1 << 20;
    for (std::size_t i = 1; i < xs.size(); ++i) min_gap = std::min(min_gap, xs[i] - xs[i - 1]);
    for (std::size_t i = 1; i < ys.size(); ++i) min_gap = std::min(min_gap, ys[i] - ys[i - 1]);
    Mesh m = grid_mesh(w, h, xs, ys, std::max(0, (min_gap - 1) / 2 - 1), rng);
    if (!all_positive(m)) m = grid_mesh(w, h, xs, ys, 0, rng);
    ASSERT_TRUE(all_positive(m));
    std::vector<std::int16_t> vd;
    std::uniform_int_distribution<int> dv(-3000, 3000);
    for (std::size_t i = 0; i < m.vertices.size(); ++i)
      vd.push_back(trial % 10 == 0 && i % 7 == 3 ? kInvalidDispQ4 : static_cast<std::int16_t>(dv(rng)));
    const ImageS16 ref = reference::interpolate(m, vd);
    const int n_tri = static_cast<int>(m.triangles.size());
    const int split = std::uniform_int_distribution<int>(0, n_tri)(rng);
    ImageS16 out(w, h, 1, kUnset);
    interpolate_triangles(m, vd.data(), split, n_tri, out.view());
    interpolate_triangles(m, vd.data(), 0, split, out.view());
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        ASSERT_EQ(out.at(x, y), ref.at(x, y)) << "trial " << trial << " pixel " << x << "," << y;
  }
}

TEST(Interpolate, EqualsReferenceOnTritreeMeshesOfMiddlebury) {
  TRISTEREO_REQUIRE_MIDDLEBURY();
  // Real meshes: slanted edges of every length, long thin triangles, border
  // vertices everywhere. Disparities are random, so every pixel is rounded.
  std::mt19937 rng(6);
  for (const char* scene : {"tsukuba", "cones"}) {
    const ImageU8 gray = to_gray(read_image_u8(test::data_set_dir("middlebury") + "/" + scene + "/left.png"));
    for (int area : {16, 100, 1024}) {
      Tritree tree;
      const Mesh m = test::tritree_mesh(tree, gray, area);
      ASSERT_GT(m.triangles.size(), 2u);
      std::vector<std::int16_t> vd;
      std::uniform_int_distribution<int> dv(-1000, 1000);
      for (std::size_t i = 0; i < m.vertices.size(); ++i)
        vd.push_back(i % 101 == 7 ? kInvalidDispQ4 : static_cast<std::int16_t>(dv(rng)));
      const ImageS16 ref = reference::interpolate(m, vd);
      const ImageS16 out = interpolate_all(m, vd);
      for (int y = 0; y < m.height; ++y)
        for (int x = 0; x < m.width; ++x)
          ASSERT_EQ(out.at(x, y), ref.at(x, y)) << scene << " A_max " << area << " pixel " << x << "," << y;
    }
  }
}

TEST(Interpolate, RejectsBadInputWithoutWriting) {
  std::mt19937 rng(5);
  const Mesh m = grid_mesh(10, 8, {0, 9}, {0, 7}, 0, rng);
  const std::vector<std::int16_t> vd(m.vertices.size(), 16);
  ImageS16 wrong(10, 7, 1, kUnset), right(10, 8, 1, kUnset);
  EXPECT_THROW(interpolate_triangles(m, vd.data(), 0, 2, wrong.view()), Error);
  EXPECT_THROW(interpolate_triangles(m, vd.data(), 0, 3, right.view()), Error);
  EXPECT_THROW(interpolate_triangles(m, vd.data(), -1, 1, right.view()), Error);
  EXPECT_THROW(interpolate_triangles(m, vd.data(), 2, 1, right.view()), Error);
  EXPECT_THROW(interpolate_triangles(m, nullptr, 0, 2, right.view()), Error);
  ImageView<std::int16_t> short_stride = right.view();
  short_stride.stride_bytes = 10;
  EXPECT_THROW(interpolate_triangles(m, vd.data(), 0, 2, short_stride), Error);
  for (std::int16_t v : right.pixels) ASSERT_EQ(v, kUnset);
  for (std::int16_t v : wrong.pixels) ASSERT_EQ(v, kUnset);
  interpolate_triangles(m, vd.data(), 0, 2, right.view());
  for (std::int16_t v : right.pixels) ASSERT_EQ(v, 16);
}

}  // namespace
}  // namespace tristereo
