// Golden digests of the outputs (mesh, sample disparities, dense map), committed
// once from the x86-64 float reference. Every build must reproduce them: the
// float reference and the integer pipeline (every kernel set) on x86, and the
// same on aarch64/armhf under qemu (scripts/cross-test.sh) or on a board.
//
// To regenerate after an intentional model change:
//   build/tests/print_golden_digests > tests/golden_digests.inc
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <map>

#include "support/data.hpp"
#include "support/golden_cases.hpp"
#include "support/scenes.hpp"
#include "tristereo/pipeline.hpp"
#include "tristereo/reference.hpp"
#include "tristereo/synth.hpp"
#include "tristereo/verify.hpp"

namespace tristereo {
namespace {

using test::GoldenCase;
using test::golden_cases;

const std::map<std::string, std::string>& golden() {
  static const std::map<std::string, std::string> g = {
#include "golden_digests.inc"
  };
  return g;
}

// The integer pipeline, with every kernel set this CPU runs, gives the digest.
void check_integer(const GoldenCase& c, const std::string& digest) {
  for (KernelChoice k : available_kernel_sets()) {
    Pipeline pipe;
    pipe.configure(test::unpinned_config(c.left.width, c.left.height, c.params, 2, k));
    EXPECT_EQ(digest_hex(pipe.process(c.left.view(), c.right.view())), digest)
        << c.name << " (integer, " << to_string(k) << ")";
  }
}

void check_cases(const std::vector<GoldenCase>& cases) {
  for (const GoldenCase& c : cases) {
    auto it = golden().find(c.name);
    ASSERT_NE(it, golden().end()) << "no golden digest for " << c.name;
    EXPECT_EQ(digest_hex(run_reference(c.left, c.right, c.params)), it->second)
        << c.name << " (float reference)";
    check_integer(c, it->second);
  }
}

TEST(GoldenDigest, SyntheticScenes) { check_cases(golden_cases(false)); }

TEST(GoldenDigest, Middlebury) {
  TRISTEREO_REQUIRE_MIDDLEBURY();
  std::vector<GoldenCase> all = golden_cases(true);
  all.erase(all.begin(), all.begin() + 6);  // the synthetic ones are covered above
  check_cases(all);
}

// The defaults on the scenes of the other sets: the digests are the float
// reference's (print_golden_digests); here only the integer pipeline runs, with
// every kernel set (the reference of a full frame takes minutes under the ARM
// emulators, where this suite also runs).
TEST(GoldenDigest, OtherSetsDefaults) {
  TRISTEREO_REQUIRE_ALL_DATA();
  const std::vector<GoldenCase> cases = test::golden_data_cases();
  ASSERT_EQ(cases.size(), 9u);
  for (const GoldenCase& c : cases) {
    auto it = golden().find(c.name);
    ASSERT_NE(it, golden().end()) << "no golden digest for " << c.name;
    check_integer(c, it->second);
  }
}

}  // namespace
}  // namespace tristereo
