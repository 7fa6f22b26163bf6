// Prints tests/golden_digests.inc: the float reference's digests of the golden
// cases. Run on x86-64 only after an intentional change of the model:
//   build/tests/print_golden_digests > tests/golden_digests.inc
#include <cstdio>

#include "support/golden_cases.hpp"
#include "support/scenes.hpp"
#include "tristereo/reference.hpp"
#include "tristereo/verify.hpp"

int main() {
  using namespace tristereo;
  for (const test::GoldenCase& c : test::golden_cases(test::middlebury_available()))
    std::printf("    {\"%s\", \"%s\"},\n", c.name.c_str(),
                digest_hex(run_reference(c.left, c.right, c.params)).c_str());
  return 0;
}
