// Sample and pixel state and confidence (docs/model.md section 7): what they
// mean on a scene with known ground truth, the minimum confidence's effect,
// and the float reference's maps equal to the pipeline's for the models the
// random cases of pipeline_reference_test.cpp reach least often.
#include <gtest/gtest.h>

#include <cmath>

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

SyntheticScene scene() {
  SynthParams sp;
  sp.width = 320;
  sp.height = 240;
  sp.num_disp = 48;
  return make_synthetic_scene(sp);
}

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
    EXPECT_EQ(c.measured, v.samples - v.uniqueness_rejected - v.lr_rejected);
    EXPECT_EQ(c.filled, v.filled);
    EXPECT_EQ(c.invalid, v.uniqueness_rejected + v.lr_rejected - v.filled);
    EXPECT_GT(c.filled, 0);
    EXPECT_GT(c.measured, c.filled);
  }
}

// A pixel is measured only when every vertex it is interpolated from is.
TEST(Confidence, PixelTakesTheSmallestOfItsTrianglesVertices) {
  const SyntheticScene s = scene();
  StereoParams p;
  p.num_disp = 48;
  const StereoOutput o = run(s.left, s.right, p);
  int pixels_checked = 0;
  for (const Triangle& t : o.mesh.triangles) {
    std::uint8_t st = 255, cf = 255;
    for (std::int32_t v : t) {
      st = std::min(st, o.vertex_state[static_cast<std::size_t>(v)]);
      cf = std::min(cf, o.vertex_confidence[static_cast<std::size_t>(v)]);
    }
    const Vertex& a = o.mesh.vertices[static_cast<std::size_t>(t[0])];
    const Vertex& b = o.mesh.vertices[static_cast<std::size_t>(t[1])];
    const Vertex& c = o.mesh.vertices[static_cast<std::size_t>(t[2])];
    for (int y = std::min({a.y, b.y, c.y}); y <= std::max({a.y, b.y, c.y}); ++y)
      for (int x = std::min({a.x, b.x, c.x}); x <= std::max({a.x, b.x, c.x}); ++x) {
        if (!owns_pixel(a, b, c, x, y, o.mesh.width, o.mesh.height)) continue;
        ASSERT_EQ(o.pixel_state.at(x, y), st) << x << "," << y;
        ASSERT_EQ(o.pixel_confidence.at(x, y), cf) << x << "," << y;
        ++pixels_checked;
      }
  }
  EXPECT_EQ(pixels_checked, o.mesh.width * o.mesh.height);
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
