// Once configured, process() performs no heap allocation (any thread count,
// sparse or dense, box or adaptive weights, frames smaller than the maximum,
// with a frame trace recording or not).
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <utility>

#include <gtest/gtest.h>

#include "support/alloc_counter.hpp"
#include "support/scenes.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/rig.hpp"
#include "tristereo/synth.hpp"

namespace tristereo {
namespace {

using Pair = std::pair<ImageView<const std::uint8_t>, ImageView<const std::uint8_t>>;

// The same pixels in 3 channels.
ImageU8 as_rgb(const ImageU8& gray) {
  ImageU8 rgb(gray.width, gray.height, 3);
  for (std::size_t i = 0; i < gray.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c) rgb.pixels[i * 3 + c] = gray.pixels[i];
  return rgb;
}

// Configures `pipe` with c (recording into `trace` when given), then counts the
// allocations while each pair goes through it three times.
std::int64_t allocations_over(Pipeline& pipe, const PipelineConfig& c, FrameTrace* trace,
                              std::initializer_list<Pair> pairs) {
  pipe.configure(c);
  if (trace) {
    trace->reserve(c.threads, 1 << 16);
    pipe.set_trace(trace);
  }
  test::start_counting_allocations();
  for (int f = 0; f < 3; ++f)
    for (const Pair& p : pairs) pipe.process(p.first, p.second);
  return test::stop_counting_allocations();
}

TEST(NoAlloc, ProcessDoesNotAllocate) {
  SynthParams sp;
  sp.width = 200;
  sp.height = 150;
  sp.num_disp = 32;
  const SyntheticScene s = make_synthetic_scene(sp);
  sp.width = 120;
  sp.height = 90;
  const SyntheticScene small = make_synthetic_scene(sp);
  const ImageU8 rgb_l = as_rgb(s.left), rgb_r = as_rgb(s.right);
  for (int threads : {1, 2, 3}) {
    for (bool dense : {false, true}) {
      for (Weights w : {Weights::kBox, Weights::kAdaptive}) {
       for (bool traced : {false, true}) {
        if (traced && w == Weights::kAdaptive) continue;  // the trace's code is the same for both
        PipelineConfig c;
        c.max_width = 200;
        c.max_height = 150;
        c.params.num_disp = 32;
        c.params.dense = dense;
        c.params.cost.weights = w;
        // Adaptive weights run the paper's AD cost; box runs the defaults
        // (census, paths, left-right check, fill).
        if (w == Weights::kAdaptive) c.params.cost.kind = CostKind::kAd;
        // The minimum confidence's pass too (it makes samples invalid after the fill).
        if (threads == 3) c.params.validity.min_confidence = 140;
        c.threads = threads;
        c.pin_threads = false;
        Pipeline pipe;
        FrameTrace trace;
        const std::int64_t n = allocations_over(
            pipe, c, traced ? &trace : nullptr,
            {{s.left.view(), s.right.view()}, {small.left.view(), small.right.view()}, {rgb_l.view(), rgb_r.view()}});
        EXPECT_EQ(n, 0) << "threads=" << threads << " dense=" << dense << " weights=" << to_string(w)
                        << " traced=" << traced;
        // The frames really were processed, and traced when asked.
        EXPECT_GT(pipe.last_timings().total_ns, 0);
        const StereoOutput& last = pipe.process(rgb_l.view(), rgb_r.view());
        EXPECT_EQ(last.pixel_confidence.pixels.size(), rgb_l.pixels.size() / 3);
        EXPECT_EQ(last.vertex_state.size(), last.mesh.vertices.size());
        EXPECT_EQ(trace.workers() > 0 && trace.track(FrameTrace::kPipelineTrack).size() >= 9, traced);
        EXPECT_EQ(trace.dropped(), 0u);
       }
      }
    }
  }
}

// Raw frames in: the rectification stage remaps into buffers of configure(),
// gray and RGB frames alike, at 1 and 3 workers, traced or not.
TEST(NoAlloc, RawFramesDoNotAllocate) {
  SynthParams sp;
  sp.width = 160;
  sp.height = 120;
  sp.num_disp = 32;
  const SyntheticScene s = make_synthetic_scene(sp);
  const ImageU8 rgb_l = as_rgb(s.left), rgb_r = as_rgb(s.right);
  StereoRig rig;
  for (RawCamera* cam : {&rig.left, &rig.right}) {
    cam->width = 160;
    cam->height = 120;
    cam->K = {150, 0, 80, 0, 150, 60, 0, 0, 1};
    cam->dist = {-0.2, 0.05, 0.001, -0.001, 0, 0, 0, 0};
  }
  rig.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  rig.T = {-0.1, 0.002, 0};
  // A shorter focal length than alpha 0's, so that the corners see beyond the raw image.
  Rectification rect = rectify_rig(rig);
  for (std::array<double, 12>* P : {&rect.P1, &rect.P2})
    for (int i : {0, 3, 5}) (*P)[static_cast<std::size_t>(i)] *= 0.7;
  auto maps = std::make_shared<RectifyMaps>(build_rectify_maps(rig, rect));
  ASSERT_FALSE(maps->left.border.empty() && maps->right.border.empty());  // the border path runs too
  for (int threads : {1, 3}) {
    for (bool traced : {false, true}) {
      PipelineConfig c;
      c.max_width = 160;
      c.max_height = 120;
      c.params.num_disp = 32;
      c.threads = threads;
      c.pin_threads = false;
      c.rectify = maps;
      Pipeline pipe;
      FrameTrace trace;
      EXPECT_EQ(allocations_over(pipe, c, traced ? &trace : nullptr,
                                 {{s.left.view(), s.right.view()}, {rgb_l.view(), rgb_r.view()}}),
                0)
          << "threads=" << threads << " traced=" << traced;
      EXPECT_GT(pipe.last_timings().rectify_ns, 0);
      EXPECT_EQ(trace.dropped(), 0u);
    }
  }
}

// The paper's row DP with the mirrored left-right pass: its measured samples'
// confidence, the right view's fill and the minimum confidence.
TEST(NoAlloc, RowDpWithMirroredCheckAndMinConfidenceDoesNotAllocate) {
  SynthParams sp;
  sp.width = 160;
  sp.height = 120;
  sp.num_disp = 24;
  const SyntheticScene s = make_synthetic_scene(sp);
  for (int threads : {1, 3}) {
    PipelineConfig c;
    c.max_width = 160;
    c.max_height = 120;
    c.params = paper_params();
    c.params.num_disp = 24;
    c.params.validity.lr_max_diff_q4 = 16;
    c.params.validity.lr_source = LrSource::kMirroredPass;
    c.params.validity.min_confidence = 128;  // every filled sample
    c.threads = threads;
    c.pin_threads = false;
    Pipeline pipe;
    EXPECT_EQ(allocations_over(pipe, c, nullptr, {{s.left.view(), s.right.view()}}), 0) << "threads=" << threads;
    EXPECT_GT(pipe.process(s.left.view(), s.right.view()).validity.min_confidence_rejected, 0);
  }
}

// The support prior (docs/model.md section 6b): its adjacency, segments and
// planes live in buffers of configure(), at 1 and 2 workers, traced or not.
TEST(NoAlloc, SupportPriorDoesNotAllocate) {
  SynthParams sp;
  sp.width = 200;
  sp.height = 150;
  sp.num_disp = 32;
  const SyntheticScene s = make_synthetic_scene(sp);
  for (int threads : {1, 2}) {
    for (bool traced : {false, true}) {
      PipelineConfig c;
      c.max_width = 200;
      c.max_height = 150;
      c.params.num_disp = 32;
      c.params.prior.lambda_q4 = 300;
      c.threads = threads;
      c.pin_threads = false;
      Pipeline pipe;
      FrameTrace trace;
      EXPECT_EQ(allocations_over(pipe, c, traced ? &trace : nullptr, {{s.left.view(), s.right.view()}}), 0)
          << "threads=" << threads << " traced=" << traced;
      // The stage ran: it chose some samples' winners again.
      EXPECT_GT(pipe.process(s.left.view(), s.right.view()).validity.prior_redecided, 0);
    }
  }
}

TEST(NoAlloc, CounterSeesAllocations) {
  // Guards the guard: a counter that never counts would make the test above vacuous.
  test::start_counting_allocations();
  // Direct calls of the replaceable operator (new-expressions may be elided).
  void* p = ::operator new(100);
  ::operator delete(p);
  void* q = ::operator new[](10);
  ::operator delete[](q);
  EXPECT_GE(test::stop_counting_allocations(), 2);
}

}  // namespace
}  // namespace tristereo
