// Whole-frame benchmark of the integer pipeline (Google Benchmark).
//
// One registration per scene x D x sparse/dense x kernel set x thread count,
// named  frame/<scene>/D<d>/<sparse|dense>/<kernels>/t<threads>. Counters give
// the median-friendly per-stage milliseconds of the last timed iteration set
// (means over iterations) and Mdisp/s = samples * D / (cost + DP time).
// scripts/perf_report.py turns the JSON output into docs/performance.md; ratios
// (SIMD vs scalar, sparse vs dense, N threads vs 1) come from one run.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "platform/cpu_features.hpp"
#include "tristereo/gray.hpp"
#include "tristereo/io.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/synth.hpp"

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
  return pairs;
}

void bench_frame(benchmark::State& state, const Pair* pair, int ndisp, bool dense, KernelChoice k,
                 int threads) {
  PipelineConfig c;
  c.max_width = pair->left.width;
  c.max_height = pair->left.height;
  c.params.num_disp = ndisp;
  c.params.dense = dense;
  c.kernels = k;
  c.threads = threads;
  c.pin_threads = true;
  Pipeline pipe;
  pipe.configure(c);
  pipe.process(pair->left.view(), pair->right.view());  // warm-up
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
            const std::string name = "frame/" + p.name + "/D" + std::to_string(ndisp) + "/" +
                                     (dense ? "dense" : "sparse") + "/" + to_string(k) + "/t" +
                                     std::to_string(t);
            benchmark::RegisterBenchmark(name.c_str(), bench_frame, &p, ndisp, dense, k, t)
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime()
                ->MinTime(0.5);
          }
        }
      }
    }
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
