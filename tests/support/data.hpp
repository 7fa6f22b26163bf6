// The stereo data beside the project (../shared/data, see its README): one rule
// for every test that reads it, whichever set (middlebury, middlebury2014,
// kitti2015, eth3d).
//
// The rule: a test that needs a set FAILS when the set is absent, naming the
// folder it looked in, unless TRISTEREO_ALLOW_MISSING_DATA=1, which makes it
// SKIP instead (a fresh clone without ../shared). A test never quietly does
// less because data is missing.
#pragma once

#include <string>

#include <gtest/gtest.h>

namespace tristereo::test {

std::string data_root();  // $TRISTEREO_DATA_DIR, else the ../shared/data the build was configured with
std::string data_set_dir(const std::string& set);  // data_root() + "/" + set
bool data_set_available(const std::string& set);   // its datasets.tsv is readable
bool missing_data_allowed();                      // TRISTEREO_ALLOW_MISSING_DATA=1

}  // namespace tristereo::test

// In a TEST body: returns from the test (skipped or failed, by the rule above)
// when the set is absent.
#define TRISTEREO_REQUIRE_DATA(set)                                                        \
  do {                                                                                     \
    if (!::tristereo::test::data_set_available(set)) {                                     \
      if (::tristereo::test::missing_data_allowed())                                       \
        GTEST_SKIP() << "no " << ::tristereo::test::data_set_dir(set)                      \
                     << " (TRISTEREO_ALLOW_MISSING_DATA=1)";                               \
      FAIL() << "stereo data set '" << (set) << "' not found at "                          \
             << ::tristereo::test::data_set_dir(set)                                       \
             << " (put ../shared beside the project, or set TRISTEREO_ALLOW_MISSING_DATA=1 " \
                "to skip the tests that need it)";                                         \
    }                                                                                      \
  } while (0)

#define TRISTEREO_REQUIRE_MIDDLEBURY() TRISTEREO_REQUIRE_DATA("middlebury")
