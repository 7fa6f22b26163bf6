// Depth edges (docs/model.md section 4): a triangle whose vertex disparities
// spread over more than edge_spread_q4 gives each pixel it owns the disparity
// (and confidence) of the vertex nearest to it in intensity. Checked on a
// hand-made mesh with known answers, by brute force over whole pipeline
// outputs (1 and 3 workers), against the float reference's transcription, and
// for what it buys on the synthetic scene's exact ground truth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "src/interp/interpolate_edges.hpp"
#include "src/reference/ref_match.hpp"
#include "src/tritree/fill_rule.hpp"
#include "src/tritree/tritree.hpp"
#include "support/scenes.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/gray.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/reference.hpp"
#include "tristereo/synth.hpp"
#include "tristereo/verify.hpp"

namespace tristereo {
namespace {

constexpr std::int16_t kUnset = 12345;

// Two triangles of a 5 x 5 image: (0,0) (4,0) (0,4) and (4,0) (4,4) (0,4).
Mesh square_mesh() {
  Mesh m;
  m.width = 5;
  m.height = 5;
  m.vertices = {{0, 0}, {4, 0}, {0, 4}, {4, 4}};
  m.triangles = {{0, 1, 2}, {1, 3, 2}};
  return m;
}

TEST(DepthEdges, PixelsTakeTheVertexNearestInIntensity) {
  const Mesh m = square_mesh();
  ImageU8 gray(5, 5, 1, 0);
  // Left column dark (10), the rest bright (200); the vertices: (0,0) 10,
  // (4,0) 200, (0,4) 10, (4,4) 200.
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 5; ++x) gray.at(x, y) = x == 0 ? 10 : 200;
  const std::vector<std::int16_t> vd = {16 * 30, 16 * 5, 16 * 30, 16 * 5};
  ImageS16 out(5, 5, 1, kUnset);
  interpolate_edge_triangles(m, vd.data(), gray.view(), 48, 0, 2, out.view());
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 5; ++x) {
      // Every pixel lies in one of the two triangles, and both straddle the edge
      // (spread 25 px > 3 px).
      EXPECT_EQ(out.at(x, y), x == 0 ? 16 * 30 : 16 * 5) << x << "," << y;
    }
  // Not above the spread: nothing written.
  ImageS16 untouched(5, 5, 1, kUnset);
  interpolate_edge_triangles(m, vd.data(), gray.view(), 16 * 25, 0, 2, untouched.view());
  interpolate_edge_triangles(m, vd.data(), gray.view(), 0, 0, 2, untouched.view());
  for (std::int16_t v : untouched.pixels) EXPECT_EQ(v, kUnset);
  // An invalid vertex: its triangle is left to invalidate_triangles.
  std::vector<std::int16_t> with_invalid = vd;
  with_invalid[1] = kInvalidDispQ4;
  ImageS16 none(5, 5, 1, kUnset);
  interpolate_edge_triangles(m, with_invalid.data(), gray.view(), 48, 0, 2, none.view());
  for (std::int16_t v : none.pixels) EXPECT_EQ(v, kUnset);
}

TEST(DepthEdges, TiesGoToTheSmallerDisparityThenTheSmallerConfidence) {
  const Mesh m = square_mesh();
  ImageU8 gray(5, 5, 1, 100);  // every pixel as near to every vertex
  std::vector<std::int16_t> vd = {16 * 9, 16 * 2, 16 * 7, 16 * 2};
  std::vector<std::uint8_t> vc = {200, 180, 140, 130};
  ImageS16 disp(5, 5, 1, kUnset);
  ImageU8 conf(5, 5, 1, 0), state(5, 5, 1, 0);
  const ConfidenceMaps maps{vc.data(), conf.view(), state.view()};
  interpolate_edge_triangles(m, vd.data(), gray.view(), 16, 0, 2, disp.view(), &maps);
  // Triangle 0 (vertices 0, 1, 2): vertex 1 (2 px); triangle 1 (1, 3, 2):
  // vertices 1 and 3 both 2 px, 3 the less confident. A vertex's own pixel
  // keeps its own value.
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 5; ++x) {
      const bool first = owns_pixel(m.vertices[0], m.vertices[1], m.vertices[2], x, y, 5, 5);
      int id = first ? 1 : 3;
      for (int v = 0; v < 4; ++v)
        if (m.vertices[static_cast<std::size_t>(v)].x == x && m.vertices[static_cast<std::size_t>(v)].y == y) id = v;
      EXPECT_EQ(disp.at(x, y), vd[static_cast<std::size_t>(id)]) << x << "," << y;
      EXPECT_EQ(conf.at(x, y), vc[static_cast<std::size_t>(id)]) << x << "," << y;
      EXPECT_EQ(state.at(x, y), 2) << x << "," << y;
    }
}

// The same on triangles small enough for the owned-pixel table (corners
// within 2 pixels, away from the last row and column): a corner's own pixel
// keeps its value even where another corner ties with it and is nearer.
TEST(DepthEdges, SmallTrianglesKeepTheirCornersOwnPixels) {
  Mesh m;
  m.width = 7;
  m.height = 7;
  m.vertices = {{2, 2}, {4, 2}, {2, 4}, {4, 4}};
  m.triangles = {{0, 1, 2}, {1, 3, 2}};
  ImageU8 gray(7, 7, 1, 50);
  const std::vector<std::int16_t> vd = {16 * 12, 16 * 3, 16 * 8, 16 * 3};
  const std::vector<std::uint8_t> vc = {250, 129, 140, 128};
  ImageS16 disp(7, 7, 1, kUnset);
  ImageU8 conf(7, 7, 1, 0), state(7, 7, 1, 0);
  const ConfidenceMaps maps{vc.data(), conf.view(), state.view()};
  interpolate_edge_triangles(m, vd.data(), gray.view(), 16, 0, 2, disp.view(), &maps);
  int corners = 0;
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 7; ++x) {
      int tri = -1;
      for (int t = 0; t < 2; ++t) {
        const Triangle& tr = m.triangles[static_cast<std::size_t>(t)];
        if (owns_pixel(m.vertices[static_cast<std::size_t>(tr[0])], m.vertices[static_cast<std::size_t>(tr[1])],
                       m.vertices[static_cast<std::size_t>(tr[2])], x, y, 7, 7))
          tri = t;
      }
      if (tri < 0) {
        EXPECT_EQ(disp.at(x, y), kUnset) << x << "," << y;
        continue;
      }
      int id = tri == 0 ? 1 : 3;  // ties: the smaller disparity, then the less confident
      for (int v = 0; v < 4; ++v)
        if (m.vertices[static_cast<std::size_t>(v)].x == x && m.vertices[static_cast<std::size_t>(v)].y == y) {
          id = v;
          ++corners;
        }
      EXPECT_EQ(disp.at(x, y), vd[static_cast<std::size_t>(id)]) << x << "," << y;
      EXPECT_EQ(conf.at(x, y), vc[static_cast<std::size_t>(id)]) << x << "," << y;
    }
  // Of the four corners these two triangles own (2, 2) alone (the rest belong
  // to triangles a whole mesh would have around them); it has the largest
  // disparity, so the tie would take it elsewhere.
  EXPECT_EQ(corners, 1);
  EXPECT_EQ(disp.at(2, 2), 16 * 12);
}

// The pipeline writes a row of tiles' depth edges right after its tiles,
// which write the pixels of its own rows (half-open, the last row of tiles
// through the image's last row): so its triangles must own no pixel of
// another row of tiles. The fill rule gives the line between two rows of
// tiles to the triangles below it. Random images, sizes (stretched sides,
// partial tiles) and tritree parameters.
TEST(DepthEdges, ARowOfTilesTrianglesOwnOnlyItsRows) {
  test::Rng rng(4040);
  int checked = 0;
  for (int round = 0; round < 60; ++round) {
    const int w = rng.uniform(3, 140), h = rng.uniform(3, 140);
    Tritree tree;
    const Mesh m = test::random_mesh(rng, w, h, tree);
    const TritreeGrid g = tree.grid();
    if (g.need == nullptr) continue;  // a 2-pixel strip: one pass over its two triangles
    const RtinLayout& L = g.layout;
    for (int ty = 0; ty < L.tiles_y; ++ty) {
      const std::size_t t0 = g.band_start[ty];
      const std::size_t t1 = ty + 1 < L.tiles_y ? g.band_start[ty + 1] : m.triangles.size();
      const int y_lo = L.real_y(ty * L.tile);
      const int y_end = ty + 1 < L.tiles_y ? L.real_y((ty + 1) * L.tile) : h;
      for (std::size_t t = t0; t < t1; ++t) {
        const Triangle& tr = m.triangles[t];
        const Vertex& a = m.vertices[static_cast<std::size_t>(tr[0])];
        const Vertex& b = m.vertices[static_cast<std::size_t>(tr[1])];
        const Vertex& c = m.vertices[static_cast<std::size_t>(tr[2])];
        for (int y = std::min({a.y, b.y, c.y}); y <= std::max({a.y, b.y, c.y}); ++y)
          for (int x = std::min({a.x, b.x, c.x}); x <= std::max({a.x, b.x, c.x}); ++x)
            if (owns_pixel(a, b, c, x, y, w, h)) {
              ASSERT_GE(y, y_lo) << w << "x" << h << " row of tiles " << ty << " triangle " << t;
              ASSERT_LT(y, y_end) << w << "x" << h << " row of tiles " << ty << " triangle " << t;
              ++checked;
            }
      }
    }
  }
  EXPECT_GT(checked, 100000);
}

StereoOutput run(const SyntheticScene& s, const StereoParams& p, int threads) {
  Pipeline pipe;
  pipe.configure(test::unpinned_config(s.left.width, s.left.height, p, threads));
  return pipe.process(s.left.view(), s.right.view());
}

// Whole frames: every pixel of a straddling triangle by the rule, every other
// pixel by its plane (the reference's plane interpolation), on two sizes (one
// with stretched sides) and 1 and 3 workers.
TEST(DepthEdges, WholeFramesFollowTheRulePixelByPixel) {
  for (const auto& wh : {std::pair<int, int>{320, 240}, {161, 97}}) {
    const SyntheticScene s = test::synthetic_scene(wh.first, wh.second, 48);
    const ImageU8 gray = to_gray(s.left);
    for (int threads : {1, 3}) {
      StereoParams p;
      p.num_disp = 48;
      const StereoOutput o = run(s, p, threads);
      const Mesh& m = o.mesh;
      const ImageS16 planes = reference::interpolate(m, o.vertex_disp_q4);
      int straddling = 0, moved = 0;
      for (const Triangle& t : m.triangles) {
        int d[3];
        bool valid = true;
        for (int k = 0; k < 3; ++k) {
          d[k] = o.vertex_disp_q4[static_cast<std::size_t>(t[static_cast<std::size_t>(k)])];
          valid = valid && d[k] != kInvalidDispQ4;
        }
        const bool edge = valid && *std::max_element(d, d + 3) - *std::min_element(d, d + 3) > p.interp.edge_spread_q4;
        straddling += edge ? 1 : 0;
        const Vertex& a = m.vertices[static_cast<std::size_t>(t[0])];
        const Vertex& b = m.vertices[static_cast<std::size_t>(t[1])];
        const Vertex& c = m.vertices[static_cast<std::size_t>(t[2])];
        for (int y = std::min({a.y, b.y, c.y}); y <= std::max({a.y, b.y, c.y}); ++y)
          for (int x = std::min({a.x, b.x, c.x}); x <= std::max({a.x, b.x, c.x}); ++x) {
            if (!owns_pixel(a, b, c, x, y, m.width, m.height)) continue;
            if (!edge) {
              ASSERT_EQ(o.disp_q4.at(x, y), planes.at(x, y)) << x << "," << y;
              continue;
            }
            // The expected vertex: its own pixel, else nearest in intensity,
            // then smaller disparity, then smaller confidence.
            std::size_t best = 0;
            bool have = false;
            for (int k = 0; k < 3; ++k) {
              const std::size_t v = static_cast<std::size_t>(t[static_cast<std::size_t>(k)]);
              const Vertex& q = m.vertices[v];
              if (q.x == x && q.y == y) {
                best = v;
                have = true;
                break;
              }
            }
            if (!have) {
              const auto worse = [&](std::size_t u, std::size_t v) {  // is u after v in the rule's order?
                const int eu = std::abs(gray.at(x, y) - gray.at(m.vertices[u].x, m.vertices[u].y));
                const int ev = std::abs(gray.at(x, y) - gray.at(m.vertices[v].x, m.vertices[v].y));
                if (eu != ev) return eu > ev;
                if (o.vertex_disp_q4[u] != o.vertex_disp_q4[v]) return o.vertex_disp_q4[u] > o.vertex_disp_q4[v];
                return o.vertex_confidence[u] > o.vertex_confidence[v];
              };
              best = static_cast<std::size_t>(t[0]);
              for (int k = 1; k < 3; ++k) {
                const std::size_t v = static_cast<std::size_t>(t[static_cast<std::size_t>(k)]);
                if (worse(best, v)) best = v;
              }
            }
            ASSERT_EQ(o.disp_q4.at(x, y), o.vertex_disp_q4[best]) << x << "," << y;
            ASSERT_EQ(o.pixel_confidence.at(x, y), o.vertex_confidence[best]) << x << "," << y;
            ASSERT_EQ(o.pixel_state.at(x, y), o.vertex_state[best]) << x << "," << y;
            moved += o.disp_q4.at(x, y) != planes.at(x, y) ? 1 : 0;
          }
      }
      // The synthetic scene's objects give hundreds of straddling triangles.
      EXPECT_GT(straddling, 100) << wh.first << "x" << wh.second;
      EXPECT_GT(moved, 300) << wh.first << "x" << wh.second;
    }
  }
}

// The float reference's transcription gives the same maps, with and without
// the rule, and with the mirrored left-right check (whose right view is
// interpolated by the rule too).
TEST(DepthEdges, SameAsTheFloatReference) {
  const SyntheticScene s = test::synthetic_scene(200, 150, 32);
  for (int variant = 0; variant < 4; ++variant) {
    StereoParams p;
    p.num_disp = 32;
    p.interp.edge_spread_q4 = variant == 0 ? 0 : variant == 1 ? 1 : 48;
    if (variant == 3) p.validity.lr_source = LrSource::kMirroredPass;
    const StereoOutput ref = run_reference(s.left, s.right, p);
    const StereoOutput o = run(s, p, 2);
    EXPECT_EQ(digest_hex(o), digest_hex(ref)) << "variant " << variant;
    EXPECT_EQ(state_digest_hex(o), state_digest_hex(ref)) << "variant " << variant;
  }
}

// What it buys on exact ground truth: the synthetic scene's pixels more than
// 1 px off, with the rule and without.
TEST(DepthEdges, FewerBadPixelsOnTheSyntheticScene) {
  const SyntheticScene s = test::synthetic_scene(320, 240, 48);
  const auto bad = [&](int spread) {
    StereoParams p;
    p.num_disp = 48;
    p.interp.edge_spread_q4 = spread;
    const StereoOutput o = run(s, p, 2);
    int n = 0;
    for (int y = 0; y < s.left.height; ++y)
      for (int x = 0; x < s.left.width; ++x) {
        const int d = o.disp_q4.at(x, y);
        n += d == kInvalidDispQ4 || std::fabs(d / 16.0 - s.disp_left.at(x, y)) > 1.0 ? 1 : 0;
      }
    return n;
  };
  const int with = bad(48), without = bad(0);
  RecordProperty("bad_with", with);
  RecordProperty("bad_without", without);
  EXPECT_LT(with, without);
}

}  // namespace
}  // namespace tristereo
