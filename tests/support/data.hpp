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
#include <vector>

#include <gtest/gtest.h>

#include "tristereo/eval.hpp"
#include "tristereo/image.hpp"

namespace tristereo::test {

std::string data_root();  // $TRISTEREO_DATA_DIR, else the ../shared/data the build was configured with
std::string data_set_dir(const std::string& set);  // data_root() + "/" + set
bool data_set_available(const std::string& set);   // its datasets.tsv is readable
bool missing_data_allowed();                      // TRISTEREO_ALLOW_MISSING_DATA=1

// Every set of ../shared/data: middlebury (v2), middlebury2014, kitti2015, eth3d.
std::vector<std::string> data_set_names();

// How ../shared/data/README.md scores a set (all known-GT pixels unless
// nonocc; invalid = bad): v2 bad > 1 px on nonocc.png (and on all.png);
// Middlebury 2014 and ETH3D bad > 2 px; KITTI D1.
enum class DataMetric { kBad1, kBad2, kD1 };

struct DataScene {
  std::string set, name, dir;  // dir: the scene folder
  int ndisp = 0;
  ImageU8 left, right;  // as stored (RGB)
  Image<float> gt;      // px; 0 or non-finite = unknown (evaluate_disparity's rule)
  ImageU8 nonocc;       // 255 = non-occluded with GT; 0x0 when the set has no mask (KITTI, ETH3D)
  ImageU8 all;          // v2's all.png; 0x0 for the other sets (there "all" = every known pixel)
  DataMetric metric = DataMetric::kBad2;
  bool metric_on_nonocc = false;  // v2: the primary number is the nonocc one
  // The peers' numbers for this scene by `metric`, from the table of
  // ../shared/data/README.md (percent); NaN where the table has none (v2).
  double peer_sgbm = 0, peer_bm = 0, peer_libelas = 0;
};

// Every scene of `set`, images and ground truth loaded. The caller checks the
// set first with TRISTEREO_REQUIRE_DATA(set) (or TRISTEREO_REQUIRE_ALL_DATA());
// here a missing or broken file throws tristereo::Error.
std::vector<DataScene> load_data_set(const std::string& set);
// The scenes of every set, in data_set_names() order (13 today).
std::vector<DataScene> load_all_data_scenes();

// The README's number for this scene (percent): the set's metric on the set's
// region (v2: nonocc.png; otherwise every known-GT pixel).
double readme_score(const DataScene& scene, ImageView<const float> disp_px);
const char* to_string(DataMetric m);  // "bad 1 px", "bad 2 px", "D1"

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

// Every set of data_set_names(), by the same rule.
#define TRISTEREO_REQUIRE_ALL_DATA()                                \
  do {                                                              \
    for (const std::string& set_ : ::tristereo::test::data_set_names()) \
      TRISTEREO_REQUIRE_DATA(set_);                                 \
  } while (0)
