// The frame trace: storage reserved once, full tracks drop and count, a
// disabled trace records nothing; recorded from the pipeline it is well
// formed (every span closed, a worker's runs and its items never overlap,
// items inside that worker's runs or, for the caller, its frame; stages
// inside their frame) and complete
// (every path tile of every pass exactly once); and it is written as JSON.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

#include "support/scenes.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/status.hpp"
#include "tristereo/synth.hpp"
#include "tristereo/trace.hpp"

namespace tristereo {
namespace {

TEST(FrameTrace, FullTrackDropsAndCounts) {
  FrameTrace t;
  t.reserve(2, 3);
  for (int i = 0; i < 5; ++i) t.record(1, TraceKind::kRun, i, i + 1, i);
  t.record(FrameTrace::kPipelineTrack, TraceKind::kFrame, 0, 10);
  t.record(7, TraceKind::kRun, 0, 1);  // no such worker: ignored
  EXPECT_EQ(t.track(1).size(), 3u);
  EXPECT_EQ(t.track(0).size(), 0u);
  EXPECT_EQ(t.track(FrameTrace::kPipelineTrack).size(), 1u);
  EXPECT_EQ(t.dropped(), 2u);
  EXPECT_EQ(t.track(1)[2].a, 2);
  t.clear();
  EXPECT_EQ(t.track(1).size(), 0u);
  EXPECT_EQ(t.dropped(), 0u);
  t.set_enabled(false);
  t.record(0, TraceKind::kRun, 0, 1);
  EXPECT_EQ(t.track(0).size(), 0u);
  EXPECT_THROW(t.reserve(0, 4), Error);
}

bool inside(const TraceSpan& in, const TraceSpan& out) {
  return in.begin_ns >= out.begin_ns && in.end_ns <= out.end_ns;
}

// Checks the trace of `frames` frames of a w x h pair on `threads` workers.
void check_trace(const FrameTrace& t, int frames, int width, int height) {
  const auto& pipe = t.track(FrameTrace::kPipelineTrack);
  std::vector<TraceSpan> frame_spans;
  for (const TraceSpan& s : pipe) {
    EXPECT_LE(s.begin_ns, s.end_ns) << to_string(s.kind);
    if (s.kind == TraceKind::kFrame) frame_spans.push_back(s);
  }
  ASSERT_EQ(static_cast<int>(frame_spans.size()), frames);
  for (std::size_t f = 1; f < frame_spans.size(); ++f) EXPECT_GE(frame_spans[f].begin_ns, frame_spans[f - 1].end_ns);
  for (const TraceSpan& s : pipe) {
    const bool held = std::any_of(frame_spans.begin(), frame_spans.end(), [&](const TraceSpan& f) { return inside(s, f); });
    EXPECT_TRUE(held) << to_string(s.kind) << " outside every frame";
  }
  // Each pass of each frame: every (band, tile) exactly once, over all workers.
  std::map<std::tuple<int, int>, std::set<std::pair<int, int>>> tiles;  // (frame, pass) -> tiles
  std::map<std::tuple<int, int>, int> tile_count;
  for (int w = 0; w < t.workers(); ++w) {
    const auto& track = t.track(w);
    std::vector<TraceSpan> runs, items;
    for (const TraceSpan& s : track) {
      EXPECT_LE(s.begin_ns, s.end_ns) << "worker " << w << " " << to_string(s.kind);
      (s.kind == TraceKind::kRun ? runs : items).push_back(s);
    }
    const auto by_begin = [](const TraceSpan& a, const TraceSpan& b) { return a.begin_ns < b.begin_ns; };
    std::sort(runs.begin(), runs.end(), by_begin);
    std::sort(items.begin(), items.end(), by_begin);
    for (std::size_t i = 1; i < runs.size(); ++i) EXPECT_GE(runs[i].begin_ns, runs[i - 1].end_ns) << "worker " << w;
    for (std::size_t i = 1; i < items.size(); ++i)
      EXPECT_GE(items[i].begin_ns, items[i - 1].end_ns) << "worker " << w << " " << to_string(items[i].kind);
    for (const TraceSpan& it : items) {
      // The caller (worker 0) runs some work inline, outside any run (every
      // stage with one worker, a fill round too small to share): its items
      // must still lie in a frame.
      const bool in_run = std::any_of(runs.begin(), runs.end(), [&](const TraceSpan& r) { return inside(it, r); });
      const bool in_frame =
          std::any_of(frame_spans.begin(), frame_spans.end(), [&](const TraceSpan& f) { return inside(it, f); });
      EXPECT_TRUE(in_run || (w == 0 && in_frame)) << "worker " << w << " " << to_string(it.kind);
      if (it.kind != TraceKind::kPathTile) continue;
      const int f = static_cast<int>(std::find_if(frame_spans.begin(), frame_spans.end(),
                                                  [&](const TraceSpan& fs) { return inside(it, fs); }) -
                                     frame_spans.begin());
      const std::tuple<int, int> key{f, it.a};
      tiles[key].insert({it.b, it.c});
      ++tile_count[key];
    }
  }
  for (const TraceSpan& s : pipe) {
    if (s.kind != TraceKind::kPaths) continue;
    const int f = static_cast<int>(std::find_if(frame_spans.begin(), frame_spans.end(),
                                                [&](const TraceSpan& fs) { return inside(s, fs); }) -
                                   frame_spans.begin());
    const int cols = s.a, rows = s.c;
    const int bands = (height + rows - 1) / rows;
    // Up to two workers a pass is a raster (a tile a row); from three on,
    // bands of 2 rows in about a tile per worker.
    const int workers = frame_spans[static_cast<std::size_t>(f)].b;
    EXPECT_EQ(workers, t.workers());
    EXPECT_EQ(rows, workers <= 2 ? 1 : 2);
    EXPECT_EQ(cols, workers <= 2 ? 1 : std::min(workers, width / 16));
    for (int pass = 0; pass < 2; ++pass) {
      const std::tuple<int, int> key{f, pass};
      EXPECT_EQ(static_cast<int>(tiles[key].size()), bands * cols) << "frame " << f << " pass " << pass;
      EXPECT_EQ(tile_count[key], bands * cols) << "a tile twice, frame " << f << " pass " << pass;
    }
  }
  EXPECT_EQ(static_cast<int>(tiles.size()), 2 * frames);
}

TEST(FrameTrace, PipelineTraceIsWellFormedAndComplete) {
  SynthParams sp;
  sp.width = 160;
  sp.height = 120;
  sp.num_disp = 32;
  const SyntheticScene s = make_synthetic_scene(sp);
  for (int threads : {1, 2, 5}) {
    StereoParams p;
    p.num_disp = 32;
    Pipeline pipe;
    pipe.configure(test::unpinned_config(sp.width, sp.height, p, threads));
    FrameTrace trace;
    trace.reserve(threads, 1 << 15);
    pipe.set_trace(&trace);
    pipe.process(s.left.view(), s.right.view());
    pipe.process(s.left.view(), s.right.view());
    SCOPED_TRACE(::testing::Message() << threads << " workers");
    EXPECT_EQ(trace.dropped(), 0u);
    check_trace(trace, 2, sp.width, sp.height);
    // Without a trace (or with a disabled one) nothing more is recorded.
    const std::size_t before = trace.track(FrameTrace::kPipelineTrack).size();
    trace.set_enabled(false);
    pipe.process(s.left.view(), s.right.view());
    pipe.set_trace(nullptr);
    trace.set_enabled(true);
    pipe.process(s.left.view(), s.right.view());
    EXPECT_EQ(trace.track(FrameTrace::kPipelineTrack).size(), before);
  }
}

TEST(FrameTrace, WritesChromeTraceEvents) {
  FrameTrace t;
  t.reserve(2, 8);
  t.record(FrameTrace::kPipelineTrack, TraceKind::kFrame, 1000, 9000, 0);
  t.record(0, TraceKind::kRun, 2000, 3500, 0);
  t.record(1, TraceKind::kPathTile, 2100, 2345, 1, 2, 3);
  const std::string path = ::testing::TempDir() + "/trace_test.json";
  write_chrome_trace(t, path);
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string json = ss.str();
  EXPECT_NE(json.find("\"traceEvents\":["), std::string::npos);
  EXPECT_NE(json.find("{\"ph\":\"X\",\"pid\":1,\"tid\":0,\"name\":\"frame\",\"ts\":0.000,\"dur\":8.000"), std::string::npos);
  EXPECT_NE(json.find("\"tid\":2,\"name\":\"path tile\",\"ts\":1.100,\"dur\":0.245,\"args\":{\"a\":1,\"b\":2,\"c\":3}"),
            std::string::npos);
  EXPECT_NE(json.find("\"args\":{\"name\":\"worker 1\"}"), std::string::npos);
  EXPECT_THROW(write_chrome_trace(t, ::testing::TempDir() + "/no/such/dir/t.json"), Error);
}

}  // namespace
}  // namespace tristereo
