// Prints tests/golden_digests.inc: the float reference's digests of the golden
// cases. Run on x86-64 only after an intentional change of the model, with
// every set of ../shared/data present:
//   build/tests/print_golden_digests > tests/golden_digests.inc
#include <cstdio>

#include "support/data.hpp"
#include "support/golden_cases.hpp"
#include "support/scenes.hpp"
#include "tristereo/reference.hpp"
#include "tristereo/verify.hpp"

int main() {
  using namespace tristereo;
  for (const test::GoldenCase& c : test::golden_cases(test::middlebury_available()))
    std::printf("    {\"%s\", \"%s\"},\n", c.name.c_str(),
                digest_hex(run_reference(c.left, c.right, c.params)).c_str());
  bool every_set = true;
  for (const std::string& set : test::data_set_names()) every_set = every_set && test::data_set_available(set);
  if (every_set)
    for (const test::GoldenCase& c : test::golden_data_cases())
      std::printf("    {\"%s\", \"%s\"},\n", c.name.c_str(),
                  digest_hex(run_reference(c.left, c.right, c.params)).c_str());
  return 0;
}
