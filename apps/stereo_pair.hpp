// The two input images of match and verify, checked as a pair.
#pragma once

#include <string>
#include <vector>

#include "tristereo/image.hpp"

namespace tristereo::cli {

// UsageError unless exactly two positional paths were given, naming what was.
void check_two_paths(const char* command, const std::vector<std::string>& positional);

// Error kSizeMismatch naming both files when the sizes differ. A gray image
// with an RGB one is valid but suspicious: the RGB one is converted to gray
// (BT.601, as the pipeline converts RGB) and stderr says which and why.
void check_stereo_pair(const std::string& left_path, ImageU8& left, const std::string& right_path, ImageU8& right);

}  // namespace tristereo::cli
