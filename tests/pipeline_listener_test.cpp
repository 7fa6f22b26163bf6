// The stage listener sees each stage begin and end once per frame, in order,
// and the timings it brackets are the ones the pipeline reports.
#include <gtest/gtest.h>

#include <vector>

#include "support/scenes.hpp"
#include "tristereo/pipeline.hpp"

namespace tristereo {
namespace {

struct Recorder : StageListener {
  std::vector<std::pair<PipelineStage, bool>> events;
  void on_stage(PipelineStage s, bool begin) noexcept override { events.emplace_back(s, begin); }
};

TEST(PipelineListener, StagesBracketEachFrameInOrder) {
  test::Rng rng(11);
  const ImageU8 l = test::random_image(rng, 48, 32);
  const ImageU8 r = test::shifted_view(rng, l, 2, 1);
  for (bool dense : {false, true}) {
    PipelineConfig c;
    c.max_width = 48;
    c.max_height = 32;
    c.params.num_disp = 8;
    c.params.dense = dense;
    c.threads = 2;
    c.pin_threads = false;
    Pipeline p;
    p.configure(c);
    Recorder rec;
    p.set_stage_listener(&rec);
    p.process(l.view(), r.view());
    p.process(l.view(), r.view());
    const std::vector<std::pair<PipelineStage, bool>> one = {
        {PipelineStage::kTritree, true},      {PipelineStage::kTritree, false},
        {PipelineStage::kMatching, true},     {PipelineStage::kMatching, false},
        {PipelineStage::kInterpolation, true}, {PipelineStage::kInterpolation, false}};
    std::vector<std::pair<PipelineStage, bool>> two = one;
    two.insert(two.end(), one.begin(), one.end());
    EXPECT_EQ(rec.events, two);
    p.set_stage_listener(nullptr);
    p.process(l.view(), r.view());
    EXPECT_EQ(rec.events.size(), 12u);
    const FrameTimings& t = p.last_timings();
    EXPECT_GE(t.total_ns, t.tritree_ns + t.cost_aggregation_ns + t.dp_ns + t.interpolation_ns);
  }
}

}  // namespace
}  // namespace tristereo
