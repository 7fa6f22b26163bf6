// Parameterising GoogleTest suites over the kernel sets compiled into this build.
//
//   class MyTest : public ::testing::TestWithParam<tristereo::KernelChoice> {};
//   TEST_P(MyTest, Foo) { TRISTEREO_SKIP_UNLESS_RUNNABLE(GetParam()); ... }
//   INSTANTIATE_TEST_SUITE_P(Sets, MyTest,
//                            ::testing::ValuesIn(tristereo::test::simd_kernel_params()),
//                            tristereo::test::KernelParamName());
//
// Tests are named by set (".../avx2"); a set compiled in but not runnable on
// this CPU (AVX2 on an SSE2-only machine) is reported as skipped, not passed.
#pragma once

#include <algorithm>
#include <ostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tristereo/kernels.hpp"

namespace tristereo {

// So GoogleTest prints "avx2", not "4-byte object <03-00 00-00>" (found by ADL).
inline void PrintTo(KernelChoice k, std::ostream* os) { *os << to_string(k); }

namespace test {

// Every compiled set except scalar (the oracle), best last.
inline std::vector<KernelChoice> simd_kernel_params() {
  std::vector<KernelChoice> sets = compiled_kernel_sets();
  sets.erase(std::remove(sets.begin(), sets.end(), KernelChoice::kScalar), sets.end());
  return sets;
}

// Every compiled set including scalar (for pipeline-level suites).
inline std::vector<KernelChoice> all_kernel_params() { return compiled_kernel_sets(); }

inline bool kernel_set_runnable(KernelChoice k) {
  const std::vector<KernelChoice> avail = available_kernel_sets();
  return std::find(avail.begin(), avail.end(), k) != avail.end();
}

struct KernelParamName {
  std::string operator()(const ::testing::TestParamInfo<KernelChoice>& info) const {
    return to_string(info.param);
  }
};

}  // namespace test
}  // namespace tristereo

#define TRISTEREO_SKIP_UNLESS_RUNNABLE(choice)                                          \
  do {                                                                                   \
    if (!::tristereo::test::kernel_set_runnable(choice))                                 \
      GTEST_SKIP() << "kernel set '" << ::tristereo::to_string(choice)                   \
                   << "' is compiled in but this CPU cannot run it";                      \
  } while (0)
