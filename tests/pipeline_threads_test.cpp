// Identical output for every kernel set and 1 to 16 threads (more than
// cores: the wavefront's schedule then differs most from run to run), on the
// synthetic scene, every scene of ../shared/data and random parameters.
#include <gtest/gtest.h>

#include "platform/cpu_features.hpp"
#include "platform/thread_pool.hpp"
#include "support/data.hpp"
#include "support/scenes.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/synth.hpp"
#include "tristereo/verify.hpp"

namespace tristereo {
namespace {

void check_all_variants(const ImageU8& l, const ImageU8& r, const StereoParams& p, const std::string& what) {
  PipelineConfig c;
  c.max_width = l.width;
  c.max_height = l.height;
  c.params = p;
  c.kernels = KernelChoice::kScalar;
  c.threads = 1;
  c.pin_threads = false;
  Pipeline base;
  base.configure(c);
  const StereoOutput expected = base.process(l.view(), r.view());
  // Every set at 1 and 3 threads, the best set also at 2, 5 and 16 (more
  // than cores): each run is a whole frame, and the suite also runs under qemu.
  const std::vector<KernelChoice> sets = available_kernel_sets();
  for (KernelChoice k : sets) {
    const std::vector<int> counts = k == sets.back() ? std::vector<int>{1, 2, 3, 5, 16} : std::vector<int>{1, 3};
    for (int threads : counts) {
      c.kernels = k;
      c.threads = threads;
      Pipeline pipe;
      pipe.configure(c);
      EXPECT_EQ(pipe.worker_count(), threads);
      const StereoOutput& got = pipe.process(l.view(), r.view());
      EXPECT_EQ(first_difference(expected, got), "")
          << what << " kernels=" << to_string(k) << " threads=" << threads;
    }
  }
}

TEST(PipelineThreads, SyntheticSceneIdenticalAcrossThreadsAndKernels) {
  SynthParams sp;
  sp.width = 240;
  sp.height = 180;
  sp.num_disp = 48;
  const SyntheticScene s = make_synthetic_scene(sp);
  for (bool dense : {false, true}) {
    for (Weights w : {Weights::kBox, Weights::kAdaptive}) {
      StereoParams p;
      p.num_disp = 48;
      p.dense = dense;
      p.cost.weights = w;
      if (w == Weights::kAdaptive) p = [&] {  // the paper's model
        StereoParams q = paper_params();
        q.num_disp = 48;
        q.dense = dense;
        q.cost.weights = w;
        return q;
      }();
      check_all_variants(s.left, s.right, p, std::string("synthetic ") + (dense ? "dense " : "sparse ") + to_string(w));
    }
  }
}

TEST(PipelineThreads, MiddleburyIdenticalAcrossThreadsAndKernels) {
  TRISTEREO_REQUIRE_MIDDLEBURY();
  for (const std::string& name : test::middlebury_names()) {
    const test::MiddleburyPair m = test::load_middlebury(name);
    StereoParams p;
    p.num_disp = m.ndisp;
    check_all_variants(m.left, m.right, p, name + " sparse");
    // Dense mode in the paper's model on the two smaller scenes: every pixel a
    // sample is the expensive case, and the synthetic scene above covers dense
    // with the defaults.
    if (m.ndisp > 20) continue;
    StereoParams paper = paper_params();
    paper.num_disp = m.ndisp;
    paper.dense = true;
    check_all_variants(m.left, m.right, paper, name + " dense paper");
  }
}

// The default model (the path wavefront) on every scene of ../shared/data,
// best kernel set, 1 to 16 workers; and random parameters on random images.
TEST(PipelineThreads, EveryDataSceneIdenticalFromOneToSixteenWorkers) {
  TRISTEREO_REQUIRE_ALL_DATA();
  for (const test::DataScene& scene : test::load_all_data_scenes()) {
    StereoParams p;
    p.num_disp = scene.ndisp;
    const PipelineConfig one = test::unpinned_config(scene.left.width, scene.left.height, p, 1);
    Pipeline base;
    base.configure(one);
    const StereoOutput& first = base.process(scene.left.view(), scene.right.view());
    const std::string expected = digest_hex(first);
    const std::string expected_states = state_digest_hex(first);
    for (int threads : {3, 16}) {
      Pipeline pipe;
      pipe.configure(test::unpinned_config(scene.left.width, scene.left.height, p, threads));
      const StereoOutput& got = pipe.process(scene.left.view(), scene.right.view());
      EXPECT_EQ(digest_hex(got), expected) << scene.set << "/" << scene.name << " threads=" << threads;
      EXPECT_EQ(state_digest_hex(got), expected_states) << scene.set << "/" << scene.name << " threads=" << threads;
    }
  }
}

TEST(PipelineThreads, RandomParametersIdenticalFromOneToSixteenWorkers) {
  test::Rng rng(0x37);
  for (int round = 0; round < 24; ++round) {
    const int w = 16 + static_cast<int>(rng.next() % 150), h = 8 + static_cast<int>(rng.next() % 90);
    const StereoParams p = test::random_params(rng, 48);
    const ImageU8 left = test::random_image(rng, w, h);
    const ImageU8 right = test::shifted_view(rng, left, static_cast<int>(rng.next() % 12), 6);
    Pipeline base;
    base.configure(test::unpinned_config(w, h, p, 1));
    const StereoOutput& first = base.process(left.view(), right.view());
    const std::string expected = digest_hex(first);
    const std::string expected_states = state_digest_hex(first);
    const int threads = 2 + static_cast<int>(rng.next() % 15);
    Pipeline pipe;
    pipe.configure(test::unpinned_config(w, h, p, threads));
    const StereoOutput& got = pipe.process(left.view(), right.view());
    EXPECT_EQ(digest_hex(got), expected) << "round " << round << " " << w << "x" << h << " threads=" << threads;
    EXPECT_EQ(state_digest_hex(got), expected_states)
        << "round " << round << " " << w << "x" << h << " threads=" << threads;
  }
}

TEST(PipelineThreads, WorkersArePinnedToTheRequestedCpus) {
  const std::vector<int> cpus = allowed_cpus();
  ASSERT_FALSE(cpus.empty());
  PipelineConfig c;
  c.max_width = 64;
  c.max_height = 48;
  c.params.num_disp = 8;
  c.threads = 0;  // one per allowed CPU
  c.pin_threads = true;
  Pipeline pipe;
  pipe.configure(c);
  EXPECT_EQ(pipe.worker_count(), static_cast<int>(cpus.size()));
}

// The first pipeline pins this thread to one CPU; the second, configured from
// the same thread, must still get one worker per CPU the process may use.
TEST(PipelineThreads, SecondPipelineFromTheSameThreadGetsEveryCpu) {
  const std::vector<int> cpus = allowed_cpus();
  PipelineConfig c;
  c.max_width = 64;
  c.max_height = 48;
  c.params.num_disp = 8;
  Pipeline first;
  first.configure(c);
  Pipeline second;
  second.configure(c);
  EXPECT_EQ(first.worker_count(), static_cast<int>(cpus.size()));
  EXPECT_EQ(second.worker_count(), static_cast<int>(cpus.size()));
}

TEST(PipelineThreads, ReconfigureManyTimesDoesNotHangOrLeak) {
  SynthParams sp;
  sp.width = 96;
  sp.height = 64;
  sp.num_disp = 16;
  const SyntheticScene s = make_synthetic_scene(sp);
  Pipeline pipe;
  std::string first;
  for (int i = 0; i < 40; ++i) {
    PipelineConfig c;
    c.max_width = 96 + (i % 3) * 8;
    c.max_height = 64;
    c.params.num_disp = 16;
    c.threads = 1 + i % 4;
    c.pin_threads = false;
    pipe.configure(c);
    const std::string d = digest_hex(pipe.process(s.left.view(), s.right.view()));
    if (i == 0) first = d;
    EXPECT_EQ(d, first) << "iteration " << i;
  }
}

}  // namespace
}  // namespace tristereo
