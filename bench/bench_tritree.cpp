// Tritree::build on the four Middlebury left images (gray) and a 640x480
// synthetic scene, with 1 and 2 pool workers (unpinned). Named
// tritree/<image>/threads:<n>; counters report the mesh size so a run also
// shows that every thread count built the same mesh. The CPU column is the
// calling thread's CPU time: with a pool that is worker 0, which runs the
// serial propagation, i.e. the critical path when the machine has free cores
// (docs/tritree.md, "Scaling with threads").
//
//   bench_tritree --benchmark_filter='tritree/cones' --benchmark_repetitions=7
//
// The Middlebury images are read from $TRISTEREO_DATA_DIR (default: the
// project's ../shared/data); a missing image skips its benchmark.
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <string>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>

#include "platform/thread_pool.hpp"
#include "src/tritree/tritree.hpp"
#include "tristereo/gray.hpp"
#include "tristereo/io.hpp"
#include "tristereo/synth.hpp"

namespace tristereo {
namespace {

struct NamedImage {
  std::string name;
  ImageU8 gray;   // empty when the file could not be read
  std::string error;
};

NamedImage load_middlebury_left(const std::string& name) {
  const char* env = std::getenv("TRISTEREO_DATA_DIR");
  const std::string data = env ? env : std::string(TRISTEREO_BENCH_DATA_DIR);
  NamedImage out{name, {}, {}};
  try {
    out.gray = to_gray(read_image_u8(data + "/middlebury/" + name + "/left.png"));
  } catch (const std::exception& e) {
    out.error = e.what();
  }
  return out;
}

void bench_build(benchmark::State& state, const NamedImage* image) {
  if (image->gray.width == 0) {
    state.SkipWithError(("cannot read " + image->name + ": " + image->error).c_str());
    return;
  }
  const int threads = static_cast<int>(state.range(0));
  ThreadPool pool;
  pool.start(threads, {}, /*pin=*/false);
  Tritree tree;
  tree.configure(image->gray.width, image->gray.height, TritreeParams{});
  Mesh mesh;
  tree.reserve(mesh);
  // Per build, averaged: refinement rounds, workers' idle time inside
  // parallel rounds (per worker), output.
  double rounds_ms = 0, idle_ms = 0, output_ms = 0;
  for (auto _ : state) {
    tree.build(image->gray.view(), mesh, &pool);
    benchmark::DoNotOptimize(mesh.triangles.data());
    const Tritree::BuildTimes& t = tree.build_times();
    rounds_ms += t.rounds_ns / 1e6;
    idle_ms += t.round_idle_ns / 1e6 / threads;
    output_ms += t.output_ns / 1e6;
  }
  const double builds = static_cast<double>(state.iterations());
  state.counters["rounds_ms"] = rounds_ms / builds;
  state.counters["round_idle_ms"] = idle_ms / builds;
  state.counters["output_ms"] = output_ms / builds;
  state.counters["triangles"] = static_cast<double>(mesh.triangles.size());
  state.counters["vertices"] = static_cast<double>(mesh.vertices.size());
  state.counters["rounds"] = tree.rounds();
  state.counters["regions"] = tree.regions();
  state.counters["deferred"] = static_cast<double>(tree.deferred_propagations());
  state.counters["criterion_splits"] = static_cast<double>(mesh.criterion_splits);
  state.SetItemsProcessed(state.iterations() * image->gray.width * image->gray.height);
}

// Independent single-threaded builds, one per benchmark thread at once (each
// with its own tree and mesh). With 2 threads, the time per build against the
// 1-thread row is what running two tritrees side by side costs on this
// machine: the ceiling for the pooled build's speed-up, free of any sharing
// in our code (docs/performance.md).
void bench_independent(benchmark::State& state, const NamedImage* image) {
  if (image->gray.width == 0) {
    state.SkipWithError(("cannot read " + image->name + ": " + image->error).c_str());
    return;
  }
  Tritree tree;
  tree.configure(image->gray.width, image->gray.height, TritreeParams{});
  Mesh mesh;
  tree.reserve(mesh);
  for (auto _ : state) {
    tree.build(image->gray.view(), mesh);
    benchmark::DoNotOptimize(mesh.triangles.data());
  }
  state.SetItemsProcessed(state.iterations() * image->gray.width * image->gray.height);
}

std::vector<NamedImage>& images() {
  static std::vector<NamedImage> all = [] {
    std::vector<NamedImage> v;
    for (const char* name : {"tsukuba", "venus", "teddy", "cones"}) v.push_back(load_middlebury_left(name));
    SynthParams sp;  // 640 x 480
    sp.num_disp = 128;
    v.push_back(NamedImage{"synthetic640x480", make_synthetic_scene(sp).left, {}});
    return v;
  }();
  return all;
}

const bool registered = [] {
  for (const NamedImage& image : images()) {
    benchmark::RegisterBenchmark(("tritree/" + image.name).c_str(), bench_build, &image)
        ->ArgName("threads")
        ->Arg(1)
        ->Arg(2)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
    benchmark::RegisterBenchmark(("tritree_independent/" + image.name).c_str(), bench_independent, &image)
        ->Threads(1)
        ->Threads(2)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
  return true;
}();

}  // namespace
}  // namespace tristereo

BENCHMARK_MAIN();
