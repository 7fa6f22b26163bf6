// The rectification stage against OpenCV, one thread, in one Google Benchmark
// run (issue #38: rectification <= 0.1x StereoBM's frame, one worker).
//
// One VGA raw pair, ../shared/data/opencv-stereo-calib pair 01 (640x480, the
// book rig) with its OpenCV calibration (calib_opencv.yml, alpha 0):
//   rectify/book640x480/<kernels>/t1     tristereo's remap of both views
//       (remap_image: the row kernel + the border pixels), every compiled and
//       runnable kernel set
//   rectify/book640x480/opencv_remap16s  cv::remap of both views with
//       initUndistortRectifyMap's fixed-point maps (CV_16SC2 + CV_16UC1),
//       INTER_LINEAR, BORDER_CONSTANT 0: the same arithmetic
//   peer/book640x480/D64/stereobm        OpenCV StereoBM's frame on the
//       rectified pair (block 9, XSOBEL, uniqueness 10, as bench_peers)
//   stage/book640x480/D64/<best>/t<N>    tristereo's pipeline on the raw pair
//       (PipelineConfig::rectify), 1 and 2 workers; counter rectify_ms is the
//       stage (both views), total_ms the frame: the stage's scaling
// OpenCV runs with cv::setNumThreads(1). Run with repetitions in random
// interleaving and compare medians of the same run (docs/rectification.md).
// Without OpenCV only the tristereo rows exist.
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
#include "tristereo/rectify.hpp"
#include "tristereo/rig.hpp"

#include "bench_context.hpp"

#if TRISTEREO_BENCH_HAVE_OPENCV
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#endif

namespace {
using namespace tristereo;

struct RawPair {
  std::string dir;
  ImageU8 left, right;  // raw, gray
  std::shared_ptr<const RectifyMaps> maps;
  ImageU8 rect_left, rect_right;  // tristereo's rectified pair
};

const RawPair* load_pair() {
  const char* env = std::getenv("TRISTEREO_DATA_DIR");
  const std::string data = env ? env : std::string(TRISTEREO_BENCH_DATA_DIR);
  static RawPair p;
  p.dir = data + "/opencv-stereo-calib/";
  if (!std::filesystem::exists(p.dir + "calib_opencv.yml")) return nullptr;
  p.left = to_gray(read_image_u8(p.dir + "left01.png"));
  p.right = to_gray(read_image_u8(p.dir + "right01.png"));
  const StereoRig rig = read_rig(p.dir + "calib_opencv.yml");
  p.maps = std::make_shared<RectifyMaps>(build_rectify_maps(rig, rectify_rig(rig)));
  p.rect_left = ImageU8(p.maps->left.width, p.maps->left.height, 1);
  p.rect_right = ImageU8(p.maps->right.width, p.maps->right.height, 1);
  remap_image(p.maps->left, p.left.view(), p.rect_left.view());
  remap_image(p.maps->right, p.right.view(), p.rect_right.view());
  return &p;
}

void bench_remap(benchmark::State& state, const RawPair* p, KernelChoice k) {
  ImageU8 l(p->maps->left.width, p->maps->left.height, 1), r(p->maps->right.width, p->maps->right.height, 1);
  for (auto _ : state) {
    remap_image(p->maps->left, p->left.view(), l.view(), k);
    remap_image(p->maps->right, p->right.view(), r.view(), k);
    benchmark::DoNotOptimize(l.pixels.data());
    benchmark::DoNotOptimize(r.pixels.data());
    benchmark::ClobberMemory();
  }
}

void bench_stage(benchmark::State& state, const RawPair* p, KernelChoice k, int threads) {
  PipelineConfig c;
  c.max_width = p->maps->rect.width;
  c.max_height = p->maps->rect.height;
  c.params.num_disp = 64;
  c.kernels = k;
  c.threads = threads;
  c.pin_threads = false;
  c.rectify = p->maps;
  Pipeline pipe;
  pipe.configure(c);
  pipe.process(p->left.view(), p->right.view());  // warm-up: first touch of every buffer
  double rect = 0, total = 0;
  for (auto _ : state) {
    pipe.process(p->left.view(), p->right.view());
    rect += static_cast<double>(pipe.last_timings().rectify_ns);
    total += static_cast<double>(pipe.last_timings().total_ns);
  }
  const double n = static_cast<double>(state.iterations()) * 1e6;
  state.counters["rectify_ms"] = rect / n;
  state.counters["total_ms"] = total / n;
}

#if TRISTEREO_BENCH_HAVE_OPENCV
cv::Mat header(const ImageU8& im) {
  return cv::Mat(im.height, im.width, CV_8UC1, const_cast<std::uint8_t*>(im.pixels.data()),
                 static_cast<std::size_t>(im.view().stride_bytes));
}

void bench_opencv_remap(benchmark::State& state, const RawPair* p) {
  cv::FileStorage fs(p->dir + "calib_opencv.yml", cv::FileStorage::READ);
  cv::Mat M1, D1, M2, D2, R1, R2, P1, P2;
  fs["M1"] >> M1;
  fs["D1"] >> D1;
  fs["M2"] >> M2;
  fs["D2"] >> D2;
  fs["R1"] >> R1;
  fs["R2"] >> R2;
  fs["P1"] >> P1;
  fs["P2"] >> P2;
  const cv::Size size(p->left.width, p->left.height);
  cv::Mat l1, l2, r1, r2;  // CV_16SC2 (integer x, y) + CV_16UC1 (the 1/32 fractions)
  cv::initUndistortRectifyMap(M1, D1, R1, P1, size, CV_16SC2, l1, l2);
  cv::initUndistortRectifyMap(M2, D2, R2, P2, size, CV_16SC2, r1, r2);
  const cv::Mat left = header(p->left), right = header(p->right);
  cv::Mat out_l, out_r;
  cv::remap(left, out_l, l1, l2, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0));  // warm-up
  cv::remap(right, out_r, r1, r2, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0));
  for (auto _ : state) {
    cv::remap(left, out_l, l1, l2, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0));
    cv::remap(right, out_r, r1, r2, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0));
    benchmark::DoNotOptimize(out_l.data);
    benchmark::DoNotOptimize(out_r.data);
    benchmark::ClobberMemory();
  }
}

void bench_stereobm(benchmark::State& state, const RawPair* p) {
  const cv::Ptr<cv::StereoBM> bm = cv::StereoBM::create(64, 9);
  bm->setPreFilterType(cv::StereoBM::PREFILTER_XSOBEL);
  bm->setUniquenessRatio(10);
  const cv::Mat left = header(p->rect_left), right = header(p->rect_right);
  cv::Mat disp;
  bm->compute(left, right, disp);  // warm-up: allocates disp and the matcher's buffers
  for (auto _ : state) {
    bm->compute(left, right, disp);
    benchmark::DoNotOptimize(disp.data);
  }
}
#endif

benchmark::internal::Benchmark* timed(benchmark::internal::Benchmark* b) {
  return b->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.5);
}

}  // namespace

int main(int argc, char** argv) {
#if TRISTEREO_BENCH_HAVE_OPENCV
  cv::setNumThreads(1);
#endif
  const RawPair* p = load_pair();
  if (p != nullptr) {
    for (KernelChoice k : available_kernel_sets())
      timed(benchmark::RegisterBenchmark(("rectify/book640x480/" + std::string(to_string(k)) + "/t1").c_str(),
                                         bench_remap, p, k));
#if TRISTEREO_BENCH_HAVE_OPENCV
    timed(benchmark::RegisterBenchmark("rectify/book640x480/opencv_remap16s", bench_opencv_remap, p));
    timed(benchmark::RegisterBenchmark("peer/book640x480/D64/stereobm", bench_stereobm, p));
#endif
    const KernelChoice best = available_kernel_sets().back();
    for (int t : {1, 2})
      timed(benchmark::RegisterBenchmark(
          ("stage/book640x480/D64/" + std::string(to_string(best)) + "/t" + std::to_string(t)).c_str(), bench_stage,
          p, best, t));
  }
  benchmark::AddCustomContext("opencv", TRISTEREO_BENCH_HAVE_OPENCV ? "yes" : "no (no OpenCV rows)");
  benchmark::AddCustomContext("data", p != nullptr ? "opencv-stereo-calib pair 01" : "missing: no rows");
  tristereo::add_binary_context();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
