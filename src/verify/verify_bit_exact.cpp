// verify: the float reference against every runnable kernel set and thread count.
#include <algorithm>

#include "platform/thread_pool.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/reference.hpp"
#include "tristereo/verify.hpp"

namespace tristereo {

VerifyReport verify_bit_exact(const ImageU8& left, const ImageU8& right, const StereoParams& params,
                              std::vector<int> thread_counts) {
  if (thread_counts.empty()) {
    thread_counts.push_back(1);
    const int n = static_cast<int>(ThreadPool::available_cpus().size());
    if (n > 1) thread_counts.push_back(n);
  }
  VerifyReport report;
  const StereoOutput expected = run_reference(left, right, params);
  report.reference_digest = digest_hex(expected);
  report.bit_exact = true;
  for (KernelChoice k : available_kernel_sets()) {
    for (int threads : thread_counts) {
      PipelineConfig config;
      config.max_width = left.width;
      config.max_height = left.height;
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

}  // namespace tristereo
