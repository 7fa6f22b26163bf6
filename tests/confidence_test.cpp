// Sample and pixel state and confidence (docs/model.md section 7): what they
// mean on a scene with known ground truth, the minimum confidence's effect,
// and the float reference's maps equal to the pipeline's for the models the
// random cases of pipeline_reference_test.cpp reach least often.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <numeric>

#include "support/data.hpp"
#include "src/tritree/fill_rule.hpp"
#include "support/scenes.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/reference.hpp"
#include "tristereo/synth.hpp"
#include "tristereo/verify.hpp"

namespace tristereo {
namespace {

constexpr std::uint8_t kInvalid = static_cast<std::uint8_t>(SampleState::kInvalid);
constexpr std::uint8_t kFilled = static_cast<std::uint8_t>(SampleState::kFilled);
constexpr std::uint8_t kMeasured = static_cast<std::uint8_t>(SampleState::kMeasured);

StereoOutput run(const ImageU8& l, const ImageU8& r, const StereoParams& p, int threads = 2) {
  Pipeline pipe;
  pipe.configure(test::unpinned_config(l.width, l.height, p, threads));
  return pipe.process(l.view(), r.view());
}

SyntheticScene scene() { return test::synthetic_scene(320, 240, 48); }

std::uint8_t expected_state(std::uint8_t confidence) {
  return confidence == 0 ? kInvalid : confidence < kMinMeasuredConfidence ? kFilled : kMeasured;
}

// The invariants every output keeps, whatever the model.
void expect_consistent(const StereoOutput& o, const std::string& what) {
  ASSERT_EQ(o.vertex_state.size(), o.mesh.vertices.size()) << what;
  ASSERT_EQ(o.vertex_confidence.size(), o.mesh.vertices.size()) << what;
  ASSERT_EQ(o.pixel_state.pixels.size(), o.disp_q4.pixels.size()) << what;
  ASSERT_EQ(o.pixel_confidence.pixels.size(), o.disp_q4.pixels.size()) << what;
  for (std::size_t i = 0; i < o.vertex_state.size(); ++i) {
    ASSERT_EQ(o.vertex_state[i], expected_state(o.vertex_confidence[i])) << what << " vertex " << i;
    ASSERT_EQ(o.vertex_state[i] == kInvalid, o.vertex_disp_q4[i] == kInvalidDispQ4) << what << " vertex " << i;
  }
  for (std::size_t i = 0; i < o.pixel_state.pixels.size(); ++i) {
    ASSERT_EQ(o.pixel_state.pixels[i], expected_state(o.pixel_confidence.pixels[i])) << what << " pixel " << i;
    ASSERT_EQ(o.pixel_state.pixels[i] == kInvalid, o.disp_q4.pixels[i] == kInvalidDispQ4) << what << " pixel " << i;
  }
}

struct Counts {
  int measured = 0, filled = 0, invalid = 0;
};
Counts count(const std::vector<std::uint8_t>& states) {
  Counts c;
  for (std::uint8_t s : states) ++(s == kMeasured ? c.measured : s == kFilled ? c.filled : c.invalid);
  return c;
}

TEST(Confidence, StatesMatchTheValidityStageCounts) {
  const SyntheticScene s = scene();
  for (bool dense : {false, true}) {
    StereoParams p;
    p.num_disp = 48;
    p.dense = dense;
    const StereoOutput o = run(s.left, s.right, p);
    expect_consistent(o, dense ? "dense" : "sparse");
    // Samples: the vertices (sparse) or the pixels (dense).
    const Counts c = count(dense ? o.pixel_state.pixels : o.vertex_state);
    const SampleValidity& v = o.validity;
    // Invalid after matching: the checks' rejections, less the support
    // prior's recoveries, plus its losses (dense frames have no prior).
    const int invalid = v.uniqueness_rejected + v.lr_rejected - v.prior_recovered + v.prior_lost;
    if (!dense) {
      EXPECT_GT(v.prior_redecided, 0);
    }
    EXPECT_EQ(c.measured, v.samples - invalid);
    EXPECT_EQ(c.filled, v.filled);
    EXPECT_EQ(c.invalid, invalid - v.filled);
    EXPECT_GT(c.filled, 0);
    EXPECT_GT(c.measured, c.filled);
  }
}

// The pixel rule by brute force from the mesh's faces, without the
// interpolation's barycentric weights or its hierarchy: a pixel that is a
// vertex takes that vertex's confidence; one on a mesh edge (a lattice point
// strictly between its ends) the smaller of the edge's two ends; any other
// the smallest of its owning triangle's three; and 0 when its disparity is
// invalid (the triangle reaches an invalid vertex).
ImageU8 brute_force_confidence(const StereoOutput& o) {
  const Mesh& m = o.mesh;
  constexpr int kNone = 256;
  Image<int> face(m.width, m.height, 1, kNone);  // the vertex's or the edge's value
  for (std::size_t i = 0; i < m.vertices.size(); ++i)
    face.at(m.vertices[i].x, m.vertices[i].y) = o.vertex_confidence[i];
  for (const Triangle& t : m.triangles)
    for (int e = 0; e < 3; ++e) {
      const std::size_t iu = static_cast<std::size_t>(t[static_cast<std::size_t>(e)]);
      const std::size_t iv = static_cast<std::size_t>(t[static_cast<std::size_t>((e + 1) % 3)]);
      const Vertex& u = m.vertices[iu];
      const Vertex& v = m.vertices[iv];
      const int dx = v.x - u.x, dy = v.y - u.y;
      const int g = std::gcd(std::abs(dx), std::abs(dy));
      const int c = std::min(o.vertex_confidence[iu], o.vertex_confidence[iv]);
      for (int k = 1; k < g; ++k) face.at(u.x + k * dx / g, u.y + k * dy / g) = c;
    }
  ImageU8 out(m.width, m.height, 1, 0);
  for (const Triangle& t : m.triangles) {
    int least = 255;
    for (std::int32_t v : t) least = std::min<int>(least, o.vertex_confidence[static_cast<std::size_t>(v)]);
    const Vertex& a = m.vertices[static_cast<std::size_t>(t[0])];
    const Vertex& b = m.vertices[static_cast<std::size_t>(t[1])];
    const Vertex& c = m.vertices[static_cast<std::size_t>(t[2])];
    for (int y = std::min({a.y, b.y, c.y}); y <= std::max({a.y, b.y, c.y}); ++y)
      for (int x = std::min({a.x, b.x, c.x}); x <= std::max({a.x, b.x, c.x}); ++x)
        if (owns_pixel(a, b, c, x, y, m.width, m.height))
          out.at(x, y) = static_cast<std::uint8_t>(o.disp_q4.at(x, y) == kInvalidDispQ4 ? 0
                                                   : face.at(x, y) != kNone       ? face.at(x, y)
                                                                                  : least);
  }
  return out;
}

// Each pixel takes the smallest confidence of the vertices its interpolated
// disparity depends on (docs/model.md section 7), and the state that implies:
// measured only when every such vertex is. Sizes with stretched sides and
// without, invalid vertices (no fill, a minimum confidence) and not, 1 and 3
// workers. On a triangle's edges that is fewer vertices than its three, so
// some pixels there are more confident than their triangle's smallest vertex.
TEST(Confidence, PixelTakesTheSmallestOfTheVerticesItIsInterpolatedFrom) {
  int on_edges_above_triangle = 0;
  for (const auto& wh : {std::pair<int, int>{320, 240}, {161, 97}}) {
    const SyntheticScene s = test::synthetic_scene(wh.first, wh.second, 48);
    for (int variant = 0; variant < 3; ++variant) {
      StereoParams p;
      p.num_disp = 48;
      p.interp.edge_spread_q4 = 0;  // planes everywhere (depth edges: interp_edges_test.cpp)
      if (variant == 1) p.validity.fill = FillMode::kNone;
      if (variant == 2) p.validity.min_confidence = 130;
      const std::string what = std::to_string(wh.first) + "x" + std::to_string(wh.second) + " variant " +
                               std::to_string(variant);
      const StereoOutput o = run(s.left, s.right, p, 1 + 2 * (variant % 2));
      expect_consistent(o, what);
      const ImageU8 expected = brute_force_confidence(o);
      int invalid = 0;
      for (int y = 0; y < o.mesh.height; ++y)
        for (int x = 0; x < o.mesh.width; ++x) {
          ASSERT_EQ(o.pixel_confidence.at(x, y), expected.at(x, y)) << what << " pixel " << x << "," << y;
          ASSERT_EQ(o.pixel_state.at(x, y), expected_state(expected.at(x, y))) << what << " pixel " << x << "," << y;
          invalid += expected.at(x, y) == 0 ? 1 : 0;
        }
      if (variant > 0) {
        EXPECT_GT(invalid, 0) << what;
      }
      // Against the old rule, the triangle's three vertices.
      for (const Triangle& t : o.mesh.triangles) {
        std::uint8_t least = 255;
        for (std::int32_t v : t) least = std::min(least, o.vertex_confidence[static_cast<std::size_t>(v)]);
        const Vertex& a = o.mesh.vertices[static_cast<std::size_t>(t[0])];
        const Vertex& b = o.mesh.vertices[static_cast<std::size_t>(t[1])];
        const Vertex& c = o.mesh.vertices[static_cast<std::size_t>(t[2])];
        for (int y = std::min({a.y, b.y, c.y}); y <= std::max({a.y, b.y, c.y}); ++y)
          for (int x = std::min({a.x, b.x, c.x}); x <= std::max({a.x, b.x, c.x}); ++x)
            if (owns_pixel(a, b, c, x, y, o.mesh.width, o.mesh.height)) {
              ASSERT_GE(o.pixel_confidence.at(x, y), least) << what << " pixel " << x << "," << y;
              on_edges_above_triangle += o.pixel_confidence.at(x, y) > least ? 1 : 0;
            }
      }
    }
  }
  EXPECT_GT(on_edges_above_triangle, 100);
}

// On a scene with exact ground truth, measured pixels are more often right
// than filled ones, and the most confident measured half more often than the
// rest.
TEST(Confidence, MeasuredPixelsAreMoreAccurateThanFilledOnes) {
  const SyntheticScene s = scene();
  StereoParams p;
  p.num_disp = 48;
  const StereoOutput o = run(s.left, s.right, p);
  long long n[3] = {0, 0, 0}, bad[3] = {0, 0, 0};
  long long n_high = 0, bad_high = 0, n_low = 0, bad_low = 0;
  const int median = [&] {
    std::vector<int> c;
    for (std::size_t i = 0; i < o.pixel_state.pixels.size(); ++i)
      if (o.pixel_state.pixels[i] == kMeasured) c.push_back(o.pixel_confidence.pixels[i]);
    std::nth_element(c.begin(), c.begin() + static_cast<std::ptrdiff_t>(c.size() / 2), c.end());
    return c[c.size() / 2];
  }();
  for (int y = 0; y < s.left.height; ++y)
    for (int x = 0; x < s.left.width; ++x) {
      const std::uint8_t st = o.pixel_state.at(x, y);
      if (st == kInvalid) continue;
      const bool wrong = std::fabs(o.disp_q4.at(x, y) / 16.0 - s.disp_left.at(x, y)) > 1.0;
      ++n[st];
      bad[st] += wrong ? 1 : 0;
      if (st != kMeasured) continue;
      if (o.pixel_confidence.at(x, y) > median) {
        ++n_high;
        bad_high += wrong ? 1 : 0;
      } else {
        ++n_low;
        bad_low += wrong ? 1 : 0;
      }
    }
  ASSERT_GT(n[kFilled], 500);
  ASSERT_GT(n[kMeasured], 10 * n[kFilled] / 2);
  const double measured_rate = static_cast<double>(bad[kMeasured]) / static_cast<double>(n[kMeasured]);
  const double filled_rate = static_cast<double>(bad[kFilled]) / static_cast<double>(n[kFilled]);
  EXPECT_LT(2 * measured_rate, filled_rate) << "bad 1 px: measured " << measured_rate << ", filled " << filled_rate;
  ASSERT_GT(n_high, 1000);
  ASSERT_GT(n_low, 1000);
  EXPECT_LE(static_cast<double>(bad_high) / static_cast<double>(n_high),
            static_cast<double>(bad_low) / static_cast<double>(n_low));
}

TEST(Confidence, MinimumConfidenceMakesWhatIsBelowItInvalidEverywhere) {
  const SyntheticScene s = scene();
  StereoParams p;
  p.num_disp = 48;
  const StereoOutput all = run(s.left, s.right, p);
  // 1 changes nothing: every valid sample has a confidence of at least 1.
  p.validity.min_confidence = 1;
  const StereoOutput one = run(s.left, s.right, p);
  EXPECT_EQ(digest_hex(one), digest_hex(all));
  EXPECT_EQ(state_digest_hex(one), state_digest_hex(all));
  EXPECT_EQ(one.validity.min_confidence_rejected, 0);
  int previous_valid = static_cast<int>(all.pixel_state.pixels.size());
  for (int c : {100, 128, 160, 200, 255}) {
    p.validity.min_confidence = c;
    const StereoOutput o = run(s.left, s.right, p, 3);
    expect_consistent(o, "min confidence " + std::to_string(c));
    int valid = 0;
    for (std::size_t i = 0; i < o.vertex_state.size(); ++i) {
      // A vertex keeps its disparity and confidence when at or above c, and is invalid otherwise.
      if (all.vertex_confidence[i] >= c) {
        EXPECT_EQ(o.vertex_disp_q4[i], all.vertex_disp_q4[i]);
        EXPECT_EQ(o.vertex_confidence[i], all.vertex_confidence[i]);
      } else {
        EXPECT_EQ(o.vertex_state[i], kInvalid);
      }
    }
    int rejected = 0;
    for (std::size_t i = 0; i < all.vertex_confidence.size(); ++i)
      rejected += all.vertex_confidence[i] != 0 && all.vertex_confidence[i] < c ? 1 : 0;
    EXPECT_EQ(o.validity.min_confidence_rejected, rejected) << c;
    for (std::size_t i = 0; i < o.pixel_state.pixels.size(); ++i) {
      valid += o.pixel_state.pixels[i] != kInvalid ? 1 : 0;
      // Pixels that stay valid keep their disparity; none is below c.
      if (o.pixel_state.pixels[i] != kInvalid) {
        EXPECT_EQ(o.disp_q4.pixels[i], all.disp_q4.pixels[i]);
        EXPECT_GE(o.pixel_confidence.pixels[i], c);
      }
    }
    if (c >= kMinMeasuredConfidence) {
      EXPECT_EQ(count(o.pixel_state.pixels).filled, 0) << c;
    }
    if (c >= kMinMeasuredConfidence) {
      EXPECT_LT(valid, previous_valid) << c;
    } else {
      EXPECT_LE(valid, previous_valid) << c;
    }
    previous_valid = valid;
  }
}

// The row DP has no summed costs: its measured samples are all 255, and the
// minimum confidence still separates them from filled ones.
TEST(Confidence, RowDpMeasuredSamplesHaveFullConfidence) {
  const SyntheticScene s = scene();
  StereoParams p = paper_params();
  p.num_disp = 48;
  p.validity.lr_max_diff_q4 = 16;
  p.validity.lr_source = LrSource::kMirroredPass;
  const StereoOutput o = run(s.left, s.right, p);
  expect_consistent(o, "row dp");
  for (std::size_t i = 0; i < o.vertex_state.size(); ++i)
    if (o.vertex_state[i] == kMeasured) {
      EXPECT_EQ(o.vertex_confidence[i], 255);
    }
  EXPECT_GT(count(o.vertex_state).filled, 0);
}

// The reference's maps equal the pipeline's, for the stages that feed them:
// both left-right sources, the row DP, fill or not, a minimum confidence
// between the filled and the measured range, at several thread counts.
TEST(Confidence, ReferenceEqualsPipeline) {
  SynthParams sp;
  sp.width = 96;
  sp.height = 72;
  sp.num_disp = 24;
  const SyntheticScene s = make_synthetic_scene(sp);
  for (int variant = 0; variant < 6; ++variant) {
    StereoParams p = variant >= 4 ? paper_params() : StereoParams{};
    p.num_disp = 24;
    p.dense = variant == 1 || variant == 5;
    if (variant == 2 || variant >= 4) {
      p.validity.lr_source = LrSource::kMirroredPass;
      p.validity.lr_max_diff_q4 = 16;
    }
    if (variant == 3) p.validity.fill = FillMode::kNone;
    p.validity.min_confidence = variant % 2 == 0 ? 0 : 100 + 20 * variant;
    const StereoOutput ref = run_reference(s.left, s.right, p);
    expect_consistent(ref, "reference variant " + std::to_string(variant));
    for (int threads : {1, 3}) {
      const StereoOutput got = run(s.left, s.right, p, threads);
      EXPECT_EQ(first_difference(ref, got), "") << "variant " << variant << " threads " << threads;
    }
  }
}

// Real data: the reference's state and confidence equal the pipeline's on
// Tsukuba (the defaults) at 1 and 3 workers.
TEST(Confidence, ReferenceEqualsPipelineOnTsukuba) {
  TRISTEREO_REQUIRE_MIDDLEBURY();
  const test::MiddleburyPair m = test::load_middlebury("tsukuba");
  StereoParams p;
  p.num_disp = m.ndisp;
  p.validity.min_confidence = 150;
  const StereoOutput ref = run_reference(m.left, m.right, p);
  for (int threads : {1, 3}) EXPECT_EQ(first_difference(ref, run(m.left, m.right, p, threads)), "") << threads;
  EXPECT_GT(ref.validity.min_confidence_rejected, 0);
}

}  // namespace
}  // namespace tristereo
