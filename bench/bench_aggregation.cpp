// Stage benchmark of cost aggregation: MatchContext::aggregate_sample at every
// pixel of a 640x480 synthetic frame (dense mode; sparse mode runs the same
// per-sample code on fewer samples), for each kernel set this CPU can run.
// Names are aggregation/<weights>/<set>/<D>; one iteration is one frame, so the
// reported time is the stage's milliseconds per frame on one thread.
// CPU time (the default) is steadier than wall time on a shared machine.
//
//   bench_aggregation --benchmark_filter='aggregation/box/.*/128'
//                     --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <cstdint>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "src/cost/match_context.hpp"
#include "src/kernels/dispatch.hpp"
#include "tristereo/kernels.hpp"
#include "tristereo/synth.hpp"
#include "bench_context.hpp"

namespace tristereo {
namespace {

constexpr int kWidth = 640;
constexpr int kHeight = 480;

const SyntheticScene& scene() {
  static const SyntheticScene s = [] {
    SynthParams p;
    p.width = kWidth;
    p.height = kHeight;
    p.num_disp = 128;
    return make_synthetic_scene(p);
  }();
  return s;
}

void bench_frame(benchmark::State& state, KernelChoice set, Weights weights, int d) {
  StereoParams params;  // library defaults: 5x5 window, T_c 30
  params.num_disp = d;
  params.cost.weights = weights;
  MatchContext ctx(kWidth, kHeight, params, kernel_set_for(set));
  ctx.begin_frame(scene().left.view(), scene().right.view());
  ctx.prepare_right_rows(0, kHeight);
  CostScratch scratch(d);
  std::vector<std::uint16_t> cost(static_cast<std::size_t>(d) + 64);
  for (auto _ : state) {
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) {
        ctx.aggregate_sample(x, y, cost.data(), scratch);
        benchmark::DoNotOptimize(cost.data());
      }
    }
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * kWidth * kHeight);  // samples
}

void register_all() {
  for (Weights w : {Weights::kBox, Weights::kAdaptive}) {
    for (KernelChoice set : available_kernel_sets()) {
      for (int d : {64, 128}) {
        const std::string name = std::string("aggregation/") +
                                 (w == Weights::kBox ? "box" : "adaptive") + "/" +
                                 to_string(set) + "/" + std::to_string(d);
        benchmark::RegisterBenchmark(name.c_str(), bench_frame, set, w, d)
            ->Unit(benchmark::kMillisecond);
      }
    }
  }
}

}  // namespace
}  // namespace tristereo

int main(int argc, char** argv) {
  tristereo::register_all();
  tristereo::add_binary_context();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
