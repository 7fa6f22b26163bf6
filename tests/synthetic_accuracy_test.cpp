// Accuracy on synthetic scenes with exact ground truth.
#include <gtest/gtest.h>

#include <map>

#include "support/scenes.hpp"
#include "tristereo/eval.hpp"
#include "tristereo/io.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/synth.hpp"

namespace tristereo {
namespace {

// The defaults on every set of ../shared/data: tests/data_accuracy_test.cpp.

// A fronto-parallel textured plane at integer disparity: every sample away from
// the left border (where x - d has no match) and the window's reach gets exactly
// 16 d. Sub-pixel refinement is off: a parabola through absolute-difference costs
// of an asymmetric texture is not centred on the true minimum (measured: 15..17 Q4).
TEST(SyntheticAccuracy, PlanarSceneIsExactAtEverySample) {
  for (int disp : {1, 7, 20}) {
    const SyntheticScene s = make_planar_scene(160, 100, disp, 5);
    for (bool dense : {false, true}) {
      PipelineConfig c;
      c.max_width = 160;
      c.max_height = 100;
      c.params.num_disp = 32;
      c.params.dense = dense;
      c.params.dp.subpixel = false;
      c.pin_threads = false;
      Pipeline p;
      p.configure(c);
      const StereoOutput& out = p.process(s.left.view(), s.right.view());
      int checked = 0;
      for (std::size_t i = 0; i < out.mesh.vertices.size(); ++i) {
        const Vertex v = out.mesh.vertices[i];
        if (v.x < disp + 8) continue;
        EXPECT_EQ(out.vertex_disp_q4[i], 16 * disp) << "vertex (" << v.x << ", " << v.y << ") d=" << disp;
        ++checked;
      }
      EXPECT_GT(checked, 100);
      // And the dense map, interpolated from exact vertices, is exact on the same region.
      for (int y = 0; y < 100; ++y)
        for (int x = disp + 24; x < 160; ++x) ASSERT_EQ(out.disp_q4.at(x, y), 16 * disp) << x << "," << y;
    }
  }
}

// The generated scene (occlusions, slanted planes): most non-occluded pixels
// within 1 px of the exact ground truth.
TEST(SyntheticAccuracy, SyntheticSceneAgainstExactGroundTruth) {
  SynthParams sp;
  sp.width = 320;
  sp.height = 240;
  sp.num_disp = 48;
  const SyntheticScene s = make_synthetic_scene(sp);
  PipelineConfig c;
  c.max_width = 320;
  c.max_height = 240;
  c.params.num_disp = 48;
  c.pin_threads = false;
  Pipeline p;
  p.configure(c);
  const StereoOutput& out = p.process(s.left.view(), s.right.view());
  const Image<float> d = disp_q4_to_float(out.disp_q4.view());
  const BadPixelStats st = evaluate_disparity(d.view(), s.disp_left.view(), s.nonocc_mask.view());
  RecordProperty("bad_1", std::to_string(st.bad_1));
  // Measured 2.58 % (bad > 0.5 px: 2.61 %, bad > 2 px: 2.53 %): the bad pixels sit at
  // occlusion borders, where the row DP and the planes of the mesh smear edges.
  EXPECT_LE(st.bad_1, 2.8);
  EXPECT_GT(st.evaluated, 320 * 240 / 2);
}

}  // namespace
}  // namespace tristereo
