// The fixed inputs and parameters of the golden-digest test (shared with the
// generator tests/print_golden_digests.cpp).
#pragma once

#include <string>
#include <vector>

#include "tristereo/image.hpp"
#include "tristereo/params.hpp"

namespace tristereo::test {

struct GoldenCase {
  std::string name;
  ImageU8 left, right;
  StereoParams params;
};

// Synthetic cases first (6 of them), then Middlebury ones when asked.
std::vector<GoldenCase> golden_cases(bool with_middlebury);
// The defaults on every scene of ../shared/data beyond Middlebury v2
// (Middlebury 2014, KITTI 2015, ETH3D), named "<set>/<scene>_sparse_default";
// the caller checks the sets first (TRISTEREO_REQUIRE_ALL_DATA()).
std::vector<GoldenCase> golden_data_cases();

}  // namespace tristereo::test
