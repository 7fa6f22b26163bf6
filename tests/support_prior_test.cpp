// The support prior (docs/model.md section 6b): its parameters are validated,
// it moves a weakly textured slanted plane towards its ground truth, and the
// pipeline equals the float reference with it on.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "support/scenes.hpp"
#include "tristereo/fixed_point.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/status.hpp"
#include "tristereo/synth.hpp"
#include "tristereo/trace.hpp"
#include "tristereo/verify.hpp"

namespace tristereo {
namespace {

// A slanted plane d(x) = d0 + g x (left coordinates) whose texture is strong
// in a sparse grid of square patches and flat between them (plateaus one
// grey level apart, 32 px wide: no texture for the matcher); both views are rendered from the texture's
// lattice with linear interpolation along the surface, so the ground truth is
// exact. Deterministic (integer hash, no libm).
struct WeakPlane {
  ImageU8 left, right;
  Image<float> gt;
};

std::uint32_t hash(std::uint32_t a) {
  a ^= a >> 16;
  a *= 0x7feb352dU;
  a ^= a >> 15;
  a *= 0x846ca68bU;
  a ^= a >> 16;
  return a;
}

int texture(int u, int y) {
  const bool strong = (u / 8) % 5 == 0 && (y / 8) % 5 == 0;
  const std::uint32_t h = hash(static_cast<std::uint32_t>(u) * 7919u + static_cast<std::uint32_t>(y) * 104729u);
  return strong ? static_cast<int>(40 + h % 176) : 96 + u / 32 + y / 32;
}

WeakPlane weak_plane(int w, int h) {
  WeakPlane s{ImageU8(w, h, 1), ImageU8(w, h, 1), Image<float>(w, h, 1)};
  const double d0 = 6.0, g = 0.0625;  // d from 6 at x = 0 to 6 + w / 16
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      s.left.at(x, y) = static_cast<std::uint8_t>(texture(x, y));
      s.gt.at(x, y) = static_cast<float>(d0 + g * x);
      // Right pixel x shows the surface point xl with xl - d(xl) = x.
      const double xl = (x + d0) / (1.0 - g);
      const int u = static_cast<int>(std::floor(xl));
      const double f = xl - u;
      const double v = (1 - f) * texture(u, y) + f * texture(u + 1, y);
      s.right.at(x, y) = static_cast<std::uint8_t>(std::floor(v + 0.5));
    }
  return s;
}

StereoOutput run(const WeakPlane& s, const StereoParams& p) {
  Pipeline pipe;
  pipe.configure(test::unpinned_config(s.left.width, s.left.height, p, 2));
  return pipe.process(s.left.view(), s.right.view());
}

// Share of pixels (x >= 24: the left band has no match) more than 1 px off.
double bad1(const StereoOutput& o, const WeakPlane& s) {
  int bad = 0, all = 0;
  for (int y = 0; y < s.gt.height; ++y)
    for (int x = 24; x < s.gt.width; ++x) {
      ++all;
      const int v = o.disp_q4.at(x, y);
      if (v == kInvalidDispQ4 || std::fabs(v / 16.0 - s.gt.at(x, y)) > 1.0) ++bad;
    }
  return 100.0 * bad / all;
}

StereoParams params(int lambda) {
  StereoParams p;
  p.num_disp = 32;
  p.prior.lambda_q4 = lambda;
  return p;
}

TEST(SupportPrior, ValidatesItsParameters) {
  StereoParams p = params(300);
  EXPECT_NO_THROW(validate_params(p));
  const auto rejects = [](StereoParams q, const std::string& field) {
    try {
      validate_params(q);
      ADD_FAILURE() << "accepted a bad " << field;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  StereoParams q = p;
  q.prior.lambda_q4 = kMaxPathPenaltyQ4 + 1;
  rejects(q, "prior.lambda_q4");
  q = p;
  q.prior.trunc = 0;
  rejects(q, "prior.trunc");
  q = p;
  q.prior.support_conf = 127;
  rejects(q, "prior.support_conf");
  q = p;
  q.prior.plane_min = 2;
  rejects(q, "prior.plane_min");
  q = p;
  q.prior.plane_tol_q4 = 0;
  rejects(q, "prior.plane_tol_q4");
  // Dense frames and the row DP go without it: valid, and it does not apply.
  q = p;
  q.dense = true;
  EXPECT_NO_THROW(validate_params(q));
  EXPECT_FALSE(support_prior_applies(q));
  q = p;
  q.optimizer = Optimizer::kRowDp;
  q.validity.lr_source = LrSource::kMirroredPass;
  EXPECT_NO_THROW(validate_params(q));
  EXPECT_FALSE(support_prior_applies(q));
  EXPECT_TRUE(support_prior_applies(p));
  q = p;
  q.prior.lambda_q4 = 0;
  EXPECT_FALSE(support_prior_applies(q));
}

// On by default (lambda 300), off in the paper's model; off, it changes nothing.
TEST(SupportPrior, OnByDefaultOffInThePaperModel) {
  EXPECT_EQ(StereoParams{}.prior.lambda_q4, 300);
  EXPECT_TRUE(support_prior_applies(StereoParams{}));
  EXPECT_EQ(paper_params().prior.lambda_q4, 0);
  const WeakPlane s = weak_plane(192, 144);
  const StereoOutput a = run(s, params(0));
  EXPECT_EQ(a.validity.prior_redecided, 0);
  EXPECT_EQ(a.validity.prior_rejected, 0);
  EXPECT_EQ(a.validity.prior_recovered, 0);
  EXPECT_EQ(a.validity.prior_lost, 0);
  StereoParams dense = params(300);
  dense.dense = true;
  EXPECT_EQ(run(s, dense).validity.prior_redecided, 0);
}

TEST(SupportPrior, MovesAWeaklyTexturedSlantedPlaneTowardsItsGroundTruth) {
  const WeakPlane s = weak_plane(192, 144);
  const StereoOutput off = run(s, params(0));
  const StereoOutput on = run(s, params(300));
  EXPECT_GT(on.validity.prior_redecided, 0);
  const double b_off = bad1(off, s), b_on = bad1(on, s);
  RecordProperty("bad1_off", std::to_string(b_off));
  RecordProperty("bad1_on", std::to_string(b_on));
  EXPECT_LT(b_on, b_off - 1.0) << "bad 1 px without the prior " << b_off << " %, with it " << b_on << " %";
}

// The stage runs between pool runs; the frame around it uses every worker:
// the outputs are the same for 1 to 16 workers (oversubscribed here).
TEST(SupportPrior, IdenticalForAnyWorkerCount) {
  const WeakPlane s = weak_plane(640, 480);  // enough segments and samples for the pool's chunks
  StereoParams p = params(300);
  p.num_disp = 64;  // d reaches 46 on the right
  StereoOutput one;
  for (int threads : {1, 2, 5, 16}) {
    Pipeline pipe;
    pipe.configure(test::unpinned_config(s.left.width, s.left.height, p, threads));
    const StereoOutput o = pipe.process(s.left.view(), s.right.view());
    EXPECT_GE(o.validity.prior_redecided, 2 * 256);  // pass 2 in two chunks at least
    if (threads == 1) {
      one = o;
      continue;
    }
    EXPECT_EQ(o.disp_q4.pixels, one.disp_q4.pixels) << "threads=" << threads;
    EXPECT_EQ(o.vertex_disp_q4, one.vertex_disp_q4) << "threads=" << threads;
    EXPECT_EQ(o.vertex_confidence, one.vertex_confidence) << "threads=" << threads;
    EXPECT_EQ(o.validity, one.validity) << "threads=" << threads;
  }
}

// From 4 (scheduled) workers the counting sort and the list of samples
// decided again are shared: a second kind of roots item per level, listing
// items (set-up, c = 1), and the same outputs. One worker cut for 8 runs
// those items one after another (what the scaling model replays).
TEST(SupportPrior, SortSharedFromFourWorkersWithTheSameOutputs) {
  const WeakPlane s = weak_plane(640, 480);
  StereoParams p = params(300);
  p.num_disp = 64;  // d reaches 46 on the right
  struct Items {
    int roots = 0, listing = 0;
  };
  const auto run_traced = [&](int threads, int schedule, Items* items) {
    PipelineConfig c = test::unpinned_config(s.left.width, s.left.height, p, threads);
    c.schedule_workers = schedule;
    Pipeline pipe;
    pipe.configure(c);
    FrameTrace trace;
    trace.reserve(threads, 1 << 16);
    pipe.set_trace(&trace);
    StereoOutput o = pipe.process(s.left.view(), s.right.view());
    EXPECT_EQ(trace.dropped(), 0u);
    for (int w = 0; w < threads; ++w)
      for (const TraceSpan& t : trace.track(w)) {
        items->roots += t.kind == TraceKind::kPriorRoots ? 1 : 0;
        items->listing += t.kind == TraceKind::kPriorSetup && t.c == 1 ? 1 : 0;
      }
    return o;
  };
  Items alone, cut, shared;
  const StereoOutput a = run_traced(1, 0, &alone);
  const StereoOutput b = run_traced(1, 8, &cut);
  const StereoOutput c = run_traced(5, 0, &shared);
  EXPECT_GT(a.validity.prior_redecided, 0);
  const int chunks = (static_cast<int>(a.vertex_disp_q4.size()) + 8191) / 8192;  // of samples
  ASSERT_GE(chunks, 2);
  EXPECT_EQ(alone.roots, 2 * chunks);  // two segment levels
  EXPECT_EQ(alone.listing, 0);
  EXPECT_EQ(cut.roots, 4 * chunks);  // counted, then placed
  EXPECT_EQ(cut.listing, 2 * chunks);
  EXPECT_EQ(shared.roots, cut.roots);
  EXPECT_EQ(shared.listing, cut.listing);
  for (const StereoOutput* o : {&b, &c}) {
    EXPECT_EQ(o->disp_q4.pixels, a.disp_q4.pixels);
    EXPECT_EQ(o->vertex_disp_q4, a.vertex_disp_q4);
    EXPECT_EQ(o->vertex_confidence, a.vertex_confidence);
    EXPECT_EQ(o->validity, a.validity);
  }
}

TEST(SupportPrior, BitExactAgainstTheReference) {
  const WeakPlane s = weak_plane(96, 72);
  StereoParams p = params(300);
  StereoParams q = p;  // the other rules: no uniqueness, one segment level, mirrored check, equiangular
  q.prior.lambda_q4 = 40;
  q.prior.uniqueness_pct = 0;
  q.prior.seg_fine = 0;
  q.prior.trunc = 2;
  q.prior.support_conf = 200;
  q.validity.lr_source = LrSource::kMirroredPass;
  q.dp.subpixel_fit = SubpixelFit::kEquiangular;
  StereoParams r = p;  // the coarse level first, the smallest segments, loose planes
  r.prior.seg_fine = 12;
  r.prior.seg_coarse = 4;
  r.prior.plane_min = 3;
  r.prior.plane_tol_q4 = 64;
  for (const StereoParams& c : {p, q, r}) {
    const VerifyReport rep = verify_bit_exact(s.left, s.right, c, {1, 2});
    EXPECT_TRUE(rep.bit_exact);
    for (const VerifyCase& vc : rep.cases) EXPECT_TRUE(vc.identical) << vc.first_difference;
  }
  SynthParams sp;
  sp.width = 160;
  sp.height = 120;
  sp.num_disp = 32;
  const SyntheticScene scene = make_synthetic_scene(sp);
  StereoParams d = p;
  d.num_disp = 32;
  const VerifyReport rep = verify_bit_exact(scene.left, scene.right, d, {1, 3});
  EXPECT_TRUE(rep.bit_exact);
  for (const VerifyCase& vc : rep.cases) EXPECT_TRUE(vc.identical) << vc.first_difference;
}

}  // namespace
}  // namespace tristereo
