// Whole-frame benchmark of the integer pipeline (Google Benchmark).
//
// One registration per scene x D x sparse/dense x kernel set x thread count,
// named  frame/<scene>/D<d>/<sparse|dense>/<kernels>/t<threads>. Counters give
// the median-friendly per-stage milliseconds of the last timed iteration set
// (means over iterations) and Mdisp/s = samples * D / (cost + DP time).
// scripts/perf_report.py turns the JSON output into docs/performance-tables.md; ratios
// (SIMD vs scalar, sparse vs dense, N threads vs 1) come from one run.
// frame_pair/<scene>/D<d>/<mode>/<kernels>/t1_vs_t<N> alternates frames of a
// 1-thread and an N-thread pipeline and reports the median of the per-pair
// speed-ups (counter `speedup`). Each pair also runs N independent 1-thread
// frames at once, one per CPU of the N-thread pool: their throughput over one
// frame's (counter `ceiling`) is what this machine gives N cores at that
// moment with no sharing at all, and `of_ceiling` = speedup / ceiling is the
// part of it the parallel pipeline achieves.
// prior_pair/<scene>/D<d>/sparse/<kernels>/t1 alternates one-worker frames
// without and with the support prior: `ratio` is the median of with / without.
// census_pixels/<scene>/D<d>/<kernels> times the census work a frame does at
// every pixel in both modes: the census transform of both images and every
// pixel's Hamming costs, row by row (counter `census_pixels_ms`); perf_report.py
// takes it as the shared part of the sparse frame's lower bound
// (docs/performance.md, "Sparse against dense").
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "platform/clock.hpp"
#include "platform/cpu_features.hpp"
#include "platform/thread_pool.hpp"
#include "src/cost/match_context.hpp"
#include "src/kernels/dispatch.hpp"
#include "tristereo/gray.hpp"
#include "tristereo/io.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/synth.hpp"
#include "bench_context.hpp"

namespace {
using namespace tristereo;

struct Pair {
  std::string name;
  ImageU8 left, right;
};

std::vector<Pair> load_pairs() {
  std::vector<Pair> pairs;
  SynthParams sp;
  sp.width = 640;
  sp.height = 480;
  sp.num_disp = 128;
  const SyntheticScene s = make_synthetic_scene(sp);
  pairs.push_back({"synthetic640x480", s.left, s.right});
  const char* env = std::getenv("TRISTEREO_DATA_DIR");
  const std::string data = env ? env : std::string(TRISTEREO_BENCH_DATA_DIR);
  for (const char* name : {"tsukuba", "venus", "teddy", "cones"}) {
    const std::string dir = data + "/middlebury/" + name + "/";
    if (!std::filesystem::exists(dir + "left.png")) continue;
    pairs.push_back({name, to_gray(read_image_u8(dir + "left.png")), to_gray(read_image_u8(dir + "right.png"))});
  }
  const std::string kitti = data + "/kitti2015/000000/";
  if (std::filesystem::exists(kitti + "left.png"))
    pairs.push_back({"kitti000000", to_gray(read_image_u8(kitti + "left.png")), to_gray(read_image_u8(kitti + "right.png"))});
  return pairs;
}

// A pipeline for the pair (pinned unless `pin` is false), configured and
// warmed up by one frame.
std::unique_ptr<Pipeline> warm_pipeline(const Pair* pair, int ndisp, bool dense, KernelChoice k,
                                        int threads, bool pin = true, int prior_lambda_q4 = 0) {
  PipelineConfig c;
  c.params.prior.lambda_q4 = prior_lambda_q4;
  c.max_width = pair->left.width;
  c.max_height = pair->left.height;
  c.params.num_disp = ndisp;
  c.params.dense = dense;
  c.kernels = k;
  c.threads = threads;
  c.pin_threads = pin;
  auto pipe = std::make_unique<Pipeline>();
  pipe->configure(c);
  pipe->process(pair->left.view(), pair->right.view());
  return pipe;
}

void bench_frame(benchmark::State& state, const Pair* pair, int ndisp, bool dense, KernelChoice k,
                 int threads) {
  const std::unique_ptr<Pipeline> warm = warm_pipeline(pair, ndisp, dense, k, threads);
  Pipeline& pipe = *warm;
  double tri = 0, cost = 0, dp = 0, interp = 0, total = 0;
  std::size_t samples = 0;
  for (auto _ : state) {
    const StereoOutput& out = pipe.process(pair->left.view(), pair->right.view());
    const FrameTimings& t = pipe.last_timings();
    tri += t.tritree_ns;
    cost += t.cost_aggregation_ns;
    dp += t.dp_ns;
    interp += t.interpolation_ns;
    total += t.total_ns;
    samples = dense ? static_cast<std::size_t>(pair->left.width) * pair->left.height : out.mesh.vertices.size();
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["tritree_ms"] = tri / n / 1e6;
  state.counters["cost_ms"] = cost / n / 1e6;
  state.counters["dp_ms"] = dp / n / 1e6;
  state.counters["interp_ms"] = interp / n / 1e6;
  state.counters["total_ms"] = total / n / 1e6;
  state.counters["samples"] = static_cast<double>(samples);
  state.counters["Mdisp_per_s"] = static_cast<double>(samples) * ndisp / ((cost + dp) / n / 1e9) / 1e6;
}

// The census work at every pixel, as the matcher's cost stage does it: the
// transform of both images, then each row's per-pixel Hamming costs (here into
// one row buffer; the matcher keeps a ring of the window's rows), in bytes
// when the matcher's box sums are (descriptor bits x window pixels <= 255).
void bench_census_pixels(benchmark::State& state, const Pair* pair, int ndisp, KernelChoice k) {
  const int w = pair->left.width, h = pair->left.height;
  StereoParams params;
  params.num_disp = ndisp;
  MatchContext ctx(w, h, params, kernel_set_for(k));
  CensusScratch census;
  census.resize(w);
  const std::size_t stride = (static_cast<std::size_t>(ndisp) + 15) / 16 * 16;
  const CostParams& c = params.cost;
  const bool bytes = (c.census_w * c.census_h - 1) * c.window_w * c.window_h <= 255;
  std::vector<std::uint16_t> row(static_cast<std::size_t>(w) * stride + 64);
  double total = 0;
  for (auto _ : state) {
    const std::int64_t t0 = monotonic_ns();
    ctx.begin_frame(pair->left.view(), pair->right.view());
    ctx.prepare_right_rows(0, h, &census);
    for (int y = 0; y < h; ++y) {
      if (bytes)
        ctx.census_pixel_costs(y, reinterpret_cast<std::uint8_t*>(row.data()), stride);
      else
        ctx.census_pixel_costs(y, row.data(), stride);
      benchmark::DoNotOptimize(row.data());
    }
    benchmark::ClobberMemory();
    total += static_cast<double>(monotonic_ns() - t0);
  }
  state.counters["census_pixels_ms"] = total / static_cast<double>(state.iterations()) / 1e6;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? 0.0 : (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}

// Frames on a 1-thread and an N-thread pipeline in alternation, each timed on
// its own: the speed-up is the median over the pairs of t1 / tN. On a shared
// machine whose speed drifts over seconds, the two frames of a pair meet the
// same moment, which two separately repeated benchmarks do not.
void bench_frame_pair(benchmark::State& state, const Pair* pair, int ndisp, bool dense, KernelChoice k,
                      int threads) {
  // Both pools pin this thread (to the same first CPU); destroyed in reverse
  // order, they leave its affinity as they found it.
  const std::unique_ptr<Pipeline> many = warm_pipeline(pair, ndisp, dense, k, threads);
  const std::unique_ptr<Pipeline> one = warm_pipeline(pair, ndisp, dense, k, 1);
  // The ceiling: N unpinned 1-thread pipelines, each run by one worker of a
  // pool pinned like `many`'s.
  ThreadPool side_by_side;
  side_by_side.start(threads, {}, /*pin=*/true);
  std::vector<std::unique_ptr<Pipeline>> solo;
  for (int i = 0; i < threads; ++i) solo.push_back(warm_pipeline(pair, ndisp, dense, k, 1, /*pin=*/false));
  // Per pair: total and the three stage groups, 1 thread / N threads.
  std::vector<double> ms_one, ms_many, ratio, ratio_tritree, ratio_matching, ratio_cost, ratio_paths, ratio_fill,
      ratio_interp, ceiling, of_ceiling;
  for (auto* v : {&ms_one, &ms_many, &ratio, &ratio_tritree, &ratio_matching, &ratio_cost, &ratio_paths, &ratio_fill,
                  &ratio_interp, &ceiling, &of_ceiling})
    v->reserve(state.max_iterations);
  const auto frame = [&](Pipeline& pipe) {
    pipe.process(pair->left.view(), pair->right.view());
    return pipe.last_timings();
  };
  const auto frames_side_by_side = [&] {
    const std::int64_t t0 = monotonic_ns();
    side_by_side.run([&](int w) { solo[static_cast<std::size_t>(w)]->process(pair->left.view(), pair->right.view()); });
    return monotonic_ns() - t0;
  };
  int turn = 0;
  for (auto _ : state) {
    // The three in turn in each of three rotations, so none always follows another.
    FrameTimings a, b;
    std::int64_t together_ns = 0;
    for (int step = 0; step < 3; ++step) {
      switch ((turn + step) % 3) {
        case 0: a = frame(*one); break;
        case 1: b = frame(*many); break;
        default: together_ns = frames_side_by_side(); break;
      }
    }
    turn = (turn + 1) % 3;
    ms_one.push_back(static_cast<double>(a.total_ns) / 1e6);
    ms_many.push_back(static_cast<double>(b.total_ns) / 1e6);
    const auto r = [](std::int64_t x, std::int64_t y) { return y > 0 ? static_cast<double>(x) / y : 0.0; };
    ratio.push_back(r(a.total_ns, b.total_ns));
    ratio_tritree.push_back(r(a.tritree_ns, b.tritree_ns));
    ratio_matching.push_back(r(a.cost_aggregation_ns + a.dp_ns, b.cost_aggregation_ns + b.dp_ns));
    ratio_cost.push_back(r(a.cost_aggregation_ns, b.cost_aggregation_ns));
    ratio_paths.push_back(r(a.dp_ns, b.dp_ns));
    ratio_fill.push_back(r(a.fill_ns, b.fill_ns));
    ratio_interp.push_back(r(a.interpolation_ns, b.interpolation_ns));
    ceiling.push_back(r(std::int64_t{threads} * a.total_ns, together_ns));
    of_ceiling.push_back(r(together_ns, std::int64_t{threads} * b.total_ns));
  }
  state.counters["t1_ms"] = median(ms_one);
  state.counters["tN_ms"] = median(ms_many);
  state.counters["speedup"] = median(ratio);
  state.counters["speedup_tritree"] = median(ratio_tritree);
  state.counters["speedup_matching"] = median(ratio_matching);
  state.counters["speedup_cost"] = median(ratio_cost);
  state.counters["speedup_paths"] = median(ratio_paths);  // the optimizer's stage: path passes and decisions
  state.counters["speedup_fill"] = median(ratio_fill);
  state.counters["speedup_interp"] = median(ratio_interp);
  state.counters["ceiling"] = median(ceiling);
  state.counters["of_ceiling"] = median(of_ceiling);
  state.counters["pairs"] = static_cast<double>(ratio.size());
}

// Frames without and with the support prior (docs/model.md section 6b) in
// alternation on one worker: the median over the pairs of with / without
// (counter `ratio`), and the prior stage's share (`prior_ms`).
void bench_prior_pair(benchmark::State& state, const Pair* pair, int ndisp, KernelChoice k, int lambda_q4) {
  const std::unique_ptr<Pipeline> off = warm_pipeline(pair, ndisp, false, k, 1);
  const std::unique_ptr<Pipeline> on = warm_pipeline(pair, ndisp, false, k, 1, true, lambda_q4);
  std::vector<double> ms_off, ms_on, ratio, prior_ms;
  int turn = 0;
  for (auto _ : state) {
    FrameTimings a, b;
    for (int step = 0; step < 2; ++step) {
      if ((turn + step) % 2 == 0) {
        off->process(pair->left.view(), pair->right.view());
        a = off->last_timings();
      } else {
        on->process(pair->left.view(), pair->right.view());
        b = on->last_timings();
      }
    }
    turn ^= 1;
    ms_off.push_back(static_cast<double>(a.total_ns) / 1e6);
    ms_on.push_back(static_cast<double>(b.total_ns) / 1e6);
    ratio.push_back(a.total_ns > 0 ? static_cast<double>(b.total_ns) / static_cast<double>(a.total_ns) : 0.0);
    prior_ms.push_back(static_cast<double>(b.prior_ns) / 1e6);
  }
  state.counters["off_ms"] = median(ms_off);
  state.counters["on_ms"] = median(ms_on);
  state.counters["ratio"] = median(ratio);
  state.counters["prior_ms"] = median(prior_ms);
}

// <kind>/<scene>/D<d>/<sparse|dense>/<kernels>
std::string bench_name(const char* kind, const Pair& p, int ndisp, bool dense, KernelChoice k) {
  return std::string(kind) + "/" + p.name + "/D" + std::to_string(ndisp) + "/" + (dense ? "dense" : "sparse") +
         "/" + to_string(k);
}

}  // namespace

int main(int argc, char** argv) {
  static const std::vector<Pair> pairs = load_pairs();
  const int max_threads = static_cast<int>(allowed_cpus().size());
  for (const Pair& p : pairs) {
    const bool synthetic = p.name.rfind("synthetic", 0) == 0;
    for (int ndisp : synthetic ? std::vector<int>{64, 128} : std::vector<int>{64}) {
      for (bool dense : {false, true}) {
        for (KernelChoice k : available_kernel_sets()) {
          std::vector<int> thread_counts = {1};
          if (synthetic && k == available_kernel_sets().back())
            for (int t = 2; t <= max_threads; ++t) thread_counts.push_back(t);
          for (int t : thread_counts) {
            const std::string name = bench_name("frame", p, ndisp, dense, k) + "/t" + std::to_string(t);
            benchmark::RegisterBenchmark(name.c_str(), bench_frame, &p, ndisp, dense, k, t)
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime()
                ->MinTime(0.5);
          }
        }
      }
    }
  }
  for (const Pair& p : pairs) {
    const bool synthetic = p.name.rfind("synthetic", 0) == 0;
    const KernelChoice best = available_kernel_sets().back();
    for (int ndisp : synthetic ? std::vector<int>{64, 128} : std::vector<int>{64}) {
      const std::string name = "census_pixels/" + p.name + "/D" + std::to_string(ndisp) + "/" + to_string(best);
      benchmark::RegisterBenchmark(name.c_str(), bench_census_pixels, &p, ndisp, best)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime()
          ->MinTime(0.5);
    }
  }
  if (!pairs.empty() && max_threads > 1) {
    // The synthetic 640x480 scene (always first) at D = 64 and 128, sparse and
    // dense; Teddy and KITTI 000000 with their own ranges, sparse.
    const KernelChoice best = available_kernel_sets().back();
    struct PairRun {
      const Pair* pair;
      int ndisp;
      bool dense;
    };
    std::vector<PairRun> runs;
    for (int ndisp : {64, 128})
      for (bool dense : {false, true}) runs.push_back({&pairs.front(), ndisp, dense});
    for (const Pair& p : pairs) {
      if (p.name == "teddy") runs.push_back({&p, 64, false});
      if (p.name == "kitti000000") runs.push_back({&p, 80, false});
    }
    for (const PairRun& run : runs) {
      for (int t = 2; t <= max_threads; ++t) {
        const std::string name =
            bench_name("frame_pair", *run.pair, run.ndisp, run.dense, best) + "/t1_vs_t" + std::to_string(t);
        benchmark::RegisterBenchmark(name.c_str(), bench_frame_pair, run.pair, run.ndisp, run.dense, best, t)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime()
            // Five runs of 30 pairs: with random interleaving they land at
            // five moments of a long run, and one bad moment of a shared
            // machine moves one of the five medians, not the result.
            ->Iterations(30)
            ->Repetitions(5);
      }
    }
  }
  if (!pairs.empty()) {
    // The support prior's cost on one worker: the synthetic 640x480 scene at
    // D = 128 and KITTI 000000 at D = 80, lambda 300.
    const KernelChoice best = available_kernel_sets().back();
    for (const Pair& p : pairs) {
      const bool synthetic = &p == &pairs.front();
      if (!synthetic && p.name != "kitti000000") continue;
      const int ndisp = synthetic ? 128 : 80;
      const std::string name = bench_name("prior_pair", p, ndisp, false, best) + "/t1";
      benchmark::RegisterBenchmark(name.c_str(), bench_prior_pair, &p, ndisp, best, 300)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime()
          ->Iterations(30)
          ->Repetitions(5);
    }
  }
  tristereo::add_binary_context();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
