// verify: the float reference against every runnable kernel set and thread count.
#include <algorithm>
#include <memory>
#include <utility>

#include "platform/thread_pool.hpp"
#include "tristereo/gray.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/rectify.hpp"
#include "tristereo/rig.hpp"
#include "tristereo/reference.hpp"
#include "tristereo/verify.hpp"

namespace tristereo {

namespace {

// The reference's output against the pipeline's on (left, right) with every
// kernel set and thread count; `rectify` set: left and right are raw frames.
VerifyReport compare_with_pipelines(const StereoOutput& expected, const ImageU8& left, const ImageU8& right,
                                    int max_width, int max_height, const StereoParams& params,
                                    std::shared_ptr<const RectifyMaps> rectify, std::vector<int> thread_counts) {
  if (thread_counts.empty()) {
    thread_counts.push_back(1);
    const int n = static_cast<int>(ThreadPool::available_cpus().size());
    if (n > 1) thread_counts.push_back(n);
  }
  VerifyReport report;
  report.reference_digest = digest_hex(expected);
  report.bit_exact = true;
  for (KernelChoice k : available_kernel_sets()) {
    for (int threads : thread_counts) {
      PipelineConfig config;
      config.max_width = max_width;
      config.max_height = max_height;
      config.rectify = rectify;
      config.params = params;
      config.kernels = k;
      config.threads = threads;
      config.pin_threads = false;  // verification must run anywhere (containers, taskset)
      Pipeline pipeline;
      pipeline.configure(config);
      const StereoOutput& got = pipeline.process(left.view(), right.view());
      VerifyCase c;
      c.kernels = k;
      c.threads = threads;
      c.first_difference = first_difference(expected, got);
      c.identical = c.first_difference.empty();
      report.bit_exact = report.bit_exact && c.identical;
      report.cases.push_back(c);
    }
  }
  return report;
}

}  // namespace

VerifyReport verify_bit_exact(const ImageU8& left, const ImageU8& right, const StereoParams& params,
                              std::vector<int> thread_counts) {
  return compare_with_pipelines(run_reference(left, right, params), left, right, left.width, left.height, params,
                                nullptr, std::move(thread_counts));
}

VerifyReport verify_bit_exact_raw(const ImageU8& raw_left, const ImageU8& raw_right, const StereoRig& rig,
                                  const Rectification& rect, const StereoParams& params,
                                  std::vector<int> thread_counts) {
  auto maps = std::make_shared<RectifyMaps>(build_rectify_maps(rig, rect));
  const auto gray = [](const ImageU8& img) { return img.channels == 1 ? img : to_gray(img); };
  const ImageU8 left = reference_rectify(rig, rect, 0, gray(raw_left));
  const ImageU8 right = reference_rectify(rig, rect, 1, gray(raw_right));
  return compare_with_pipelines(run_reference(left, right, params), raw_left, raw_right, left.width, left.height,
                                params, std::move(maps), std::move(thread_counts));
}

}  // namespace tristereo
