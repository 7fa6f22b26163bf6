// tristereo against its peers, one thread, in one Google Benchmark run.
//
// Per scene, on the same gray frames (tristereo's BT.601 conversion of the
// stored RGB pairs):
//   frame/<scene>/D<d>/<sparse|dense>/<kernels>/t1   tristereo's whole frame on
//       one worker (best kernel set), with the per-stage counters tritree_ms,
//       cost_ms, dp_ms, prior_ms, interp_ms, total_ms (means over the iterations)
//   peer/<scene>/D<d>/stereobm       OpenCV StereoBM, block 9, XSOBEL prefilter
//   peer/<scene>/D<d>/sgbm3way       OpenCV StereoSGBM MODE_SGBM_3WAY, block 5
// with the parameters of ../shared/data/README.md (uniqueness 10; SGBM P1 600,
// P2 2400, speckle 100/2, disp12MaxDiff 1). OpenCV runs with
// cv::setNumThreads(1); no thread of either side is pinned, so both meet the
// machine alike. Scenes: Middlebury v2 teddy and cones at D = 64 (their 60
// levels rounded up to the multiple of 16 StereoBM needs), the synthetic
// 640x480 scene made for D = 64 and for D = 128, KITTI 2015 000000 at D = 80.
//
// scripts/perf_report.py runs this with repetitions in random interleaving and
// prints every tristereo stage as a ratio to StereoBM's frame of the same run.
// Built without OpenCV (find_package(OpenCV) failed, or
// -DCMAKE_DISABLE_FIND_PACKAGE_OpenCV=ON), only the frame/ rows exist.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "tristereo/gray.hpp"
#include "tristereo/io.hpp"
#include "tristereo/kernels.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/synth.hpp"

#include "bench_context.hpp"

#if TRISTEREO_BENCH_HAVE_OPENCV
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#endif

namespace {
using namespace tristereo;

struct Scene {
  std::string name;
  int ndisp;
  ImageU8 left, right;  // gray
};

std::vector<Scene> load_scenes() {
  std::vector<Scene> scenes;
  for (int ndisp : {64, 128}) {
    SynthParams sp;
    sp.width = 640;
    sp.height = 480;
    sp.num_disp = ndisp;
    const SyntheticScene s = make_synthetic_scene(sp);
    scenes.push_back({"synthetic640x480", ndisp, to_gray(s.left), to_gray(s.right)});
  }
  const char* env = std::getenv("TRISTEREO_DATA_DIR");
  const std::string data = env ? env : std::string(TRISTEREO_BENCH_DATA_DIR);
  struct Stored {
    const char* name;
    const char* dir;
    int ndisp;
  };
  for (const Stored& st : {Stored{"teddy", "middlebury/teddy", 64}, Stored{"cones", "middlebury/cones", 64},
                           Stored{"kitti000000", "kitti2015/000000", 80}}) {
    const std::string dir = data + "/" + st.dir + "/";
    if (!std::filesystem::exists(dir + "left.png")) continue;
    scenes.push_back({st.name, st.ndisp, to_gray(read_image_u8(dir + "left.png")),
                      to_gray(read_image_u8(dir + "right.png"))});
  }
  return scenes;
}

std::string prefix(const char* kind, const Scene& s) {
  return std::string(kind) + "/" + s.name + "/D" + std::to_string(s.ndisp);
}

// paper: the paper's model (AD, row DP, no validity), the baseline of issue
// #14's speed budget; else the defaults.
void bench_frame(benchmark::State& state, const Scene* s, bool dense, KernelChoice k, bool paper) {
  PipelineConfig c;
  c.max_width = s->left.width;
  c.max_height = s->left.height;
  if (paper) c.params = paper_params();
  c.params.num_disp = s->ndisp;
  c.params.dense = dense;
  c.kernels = k;
  c.threads = 1;
  c.pin_threads = false;
  Pipeline pipe;
  pipe.configure(c);
  pipe.process(s->left.view(), s->right.view());  // warm-up: first touch of every buffer
  double tri = 0, cost = 0, dp = 0, prior = 0, interp = 0, total = 0, right = 0, fill = 0;
  for (auto _ : state) {
    pipe.process(s->left.view(), s->right.view());
    const FrameTimings& t = pipe.last_timings();
    right += static_cast<double>(t.right_pass_ns);
    fill += static_cast<double>(t.fill_ns);
    tri += static_cast<double>(t.tritree_ns);
    cost += static_cast<double>(t.cost_aggregation_ns);
    dp += static_cast<double>(t.dp_ns);
    prior += static_cast<double>(t.prior_ns);
    interp += static_cast<double>(t.interpolation_ns);
    total += static_cast<double>(t.total_ns);
  }
  const double n = static_cast<double>(state.iterations()) * 1e6;  // ns -> ms per frame
  state.counters["tritree_ms"] = tri / n;
  state.counters["cost_ms"] = cost / n;
  state.counters["dp_ms"] = dp / n;
  state.counters["prior_ms"] = prior / n;
  state.counters["interp_ms"] = interp / n;
  state.counters["right_pass_ms"] = right / n;
  state.counters["fill_ms"] = fill / n;
  state.counters["total_ms"] = total / n;
}

#if TRISTEREO_BENCH_HAVE_OPENCV
void run_peer(benchmark::State& state, const Scene* s, cv::StereoMatcher& matcher) {
  // cv::Mat headers over the frames (no copy); OpenCV reads them only.
  const cv::Mat left(s->left.height, s->left.width, CV_8UC1, const_cast<std::uint8_t*>(s->left.pixels.data()));
  const cv::Mat right(s->right.height, s->right.width, CV_8UC1,
                      const_cast<std::uint8_t*>(s->right.pixels.data()));
  cv::Mat disp;
  matcher.compute(left, right, disp);  // warm-up: allocates disp and the matcher's buffers
  for (auto _ : state) {
    matcher.compute(left, right, disp);
    benchmark::DoNotOptimize(disp.data);
  }
}

void bench_stereobm(benchmark::State& state, const Scene* s) {
  const cv::Ptr<cv::StereoBM> bm = cv::StereoBM::create(s->ndisp, 9);
  bm->setPreFilterType(cv::StereoBM::PREFILTER_XSOBEL);
  bm->setUniquenessRatio(10);
  run_peer(state, s, *bm);
}

void bench_sgbm3way(benchmark::State& state, const Scene* s) {
  const cv::Ptr<cv::StereoSGBM> sgbm =
      cv::StereoSGBM::create(/*minDisparity=*/0, s->ndisp, /*blockSize=*/5, /*P1=*/600, /*P2=*/2400,
                             /*disp12MaxDiff=*/1, /*preFilterCap=*/0, /*uniquenessRatio=*/10,
                             /*speckleWindowSize=*/100, /*speckleRange=*/2, cv::StereoSGBM::MODE_SGBM_3WAY);
  run_peer(state, s, *sgbm);
}
#endif

}  // namespace

int main(int argc, char** argv) {
#if TRISTEREO_BENCH_HAVE_OPENCV
  cv::setNumThreads(1);
#endif
  static const std::vector<Scene> scenes = load_scenes();
  const KernelChoice best = available_kernel_sets().back();
  for (const Scene& s : scenes) {
    for (bool dense : {false, true}) {
      const std::string name = prefix("frame", s) + (dense ? "/dense/" : "/sparse/") + to_string(best) + "/t1";
      benchmark::RegisterBenchmark(name.c_str(), bench_frame, &s, dense, best, false)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime()
          ->MinTime(0.5);
    }
    const std::string paper = prefix("frame", s) + "/paper/sparse/" + to_string(best) + "/t1";
    benchmark::RegisterBenchmark(paper.c_str(), bench_frame, &s, false, best, true)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->MinTime(0.5);
#if TRISTEREO_BENCH_HAVE_OPENCV
    benchmark::RegisterBenchmark((prefix("peer", s) + "/stereobm").c_str(), bench_stereobm, &s)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->MinTime(0.5);
    benchmark::RegisterBenchmark((prefix("peer", s) + "/sgbm3way").c_str(), bench_sgbm3way, &s)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->MinTime(0.5);
#endif
  }
  benchmark::AddCustomContext("opencv", TRISTEREO_BENCH_HAVE_OPENCV ? "yes" : "no (no peer rows)");
  tristereo::add_binary_context();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
