// Tritree::build and the interpolation of its mesh on the four Middlebury
// left images (gray), KITTI 2015 000000 and a 640x480 synthetic scene.
// tritree/<image>/threads:<n> builds with a pool of n workers (the build runs
// on the calling thread; the pool is the pipeline's and stays idle);
// interpolation/<image> fills the dense map from vertex disparities (a
// smooth surface with steps, in Q4). Counters report the mesh so a run also
// shows the sample fraction.
//
//   bench_tritree --benchmark_filter='tritree/teddy' --benchmark_repetitions=7
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
#include "src/interp/interpolate_midpoints.hpp"
#include "src/kernels/dispatch.hpp"
#include "src/interp/interpolate_planes.hpp"
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

NamedImage load_left(const std::string& name, const std::string& path_in_data) {
  const char* env = std::getenv("TRISTEREO_DATA_DIR");
  const std::string data = env ? env : std::string(TRISTEREO_BENCH_DATA_DIR);
  NamedImage out{name, {}, {}};
  try {
    out.gray = to_gray(read_image_u8(data + path_in_data));
  } catch (const std::exception& e) {
    out.error = e.what();
  }
  return out;
}

NamedImage load_middlebury_left(const std::string& name) {
  return load_left(name, "/middlebury/" + name + "/left.png");
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
  // Per build, averaged: the criterion passes and the output.
  double criterion_ms = 0, output_ms = 0;
  for (auto _ : state) {
    tree.build(image->gray.view(), mesh, &pool);
    benchmark::DoNotOptimize(mesh.triangles.data());
    const Tritree::BuildTimes& t = tree.build_times();
    criterion_ms += t.criterion_ns / 1e6;
    output_ms += t.output_ns / 1e6;
  }
  const double builds = static_cast<double>(state.iterations());
  state.counters["criterion_ms"] = criterion_ms / builds;
  state.counters["output_ms"] = output_ms / builds;
  state.counters["triangles"] = static_cast<double>(mesh.triangles.size());
  state.counters["vertices"] = static_cast<double>(mesh.vertices.size());
  state.counters["sample_fraction"] =
      static_cast<double>(mesh.vertices.size()) / (image->gray.width * image->gray.height);
  state.counters["forced_splits"] = static_cast<double>(mesh.forced_splits);
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

// The dense map from the mesh's vertex disparities (pipeline stage 4, one thread).
void bench_interpolation(benchmark::State& state, const NamedImage* image) {
  if (image->gray.width == 0) {
    state.SkipWithError(("cannot read " + image->name + ": " + image->error).c_str());
    return;
  }
  const int w = image->gray.width, h = image->gray.height;
  Tritree tree;
  tree.configure(w, h, TritreeParams{});
  Mesh mesh;
  tree.reserve(mesh);
  tree.build(image->gray.view(), mesh);
  std::vector<std::int16_t> vdisp(mesh.vertices.size());
  for (std::size_t i = 0; i < vdisp.size(); ++i) {
    const Vertex& v = mesh.vertices[i];
    vdisp[i] = static_cast<std::int16_t>(16 * 20 + v.x / 3 - v.y / 5 + (v.x > w / 2 ? 160 : 0));
  }
  ImageS16 disp(w, h, 1, 0);
  const int n = static_cast<int>(mesh.triangles.size());
  const TritreeGrid grid = tree.grid();
  std::vector<std::int32_t> values(midpoint_band_values(tree.tile_side(), w));
  const KernelSet& kernels = kernel_set_for(KernelChoice::kAuto);
  const bool by_triangles = state.range(0) != 0;
  for (auto _ : state) {
    if (by_triangles) {
      interpolate_triangles(mesh, vdisp.data(), 0, n, disp.view());
    } else {
      interpolate_midpoint_tiles(grid, mesh, vdisp.data(), 0, grid.layout.tiles_y, kernels, values.data(),
                                 disp.view());
      interpolate_stretched_leaves(grid, mesh, vdisp.data(), 0, grid.stretched_count, disp.view());
    }
    benchmark::DoNotOptimize(disp.pixels.data());
  }
  state.counters["triangles"] = n;
  state.SetItemsProcessed(state.iterations() * w * h);
}

std::vector<NamedImage>& images() {
  static std::vector<NamedImage> all = [] {
    std::vector<NamedImage> v;
    for (const char* name : {"tsukuba", "venus", "teddy", "cones"}) v.push_back(load_middlebury_left(name));
    v.push_back(load_left("kitti000000", "/kitti2015/000000/left.png"));
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
    // by_triangles:0 = the pipeline's midpoint averages, 1 = one plane per triangle.
    benchmark::RegisterBenchmark(("interpolation/" + image.name).c_str(), bench_interpolation, &image)
        ->ArgName("by_triangles")
        ->Arg(0)
        ->Arg(1)
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
