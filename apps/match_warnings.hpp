// Warnings for valid but suspicious input to match: the run goes on, stderr
// says what to check. Each returns the warning text ("" when all is well), so
// the rules can be tested without a terminal.
#pragma once

#include <string>
#include <vector>

#include "tristereo/image.hpp"
#include "tristereo/io.hpp"
#include "tristereo/pipeline.hpp"

namespace tristereo::cli {

// A search range d_min .. d_min + num_disp - 1 that leaves every left pixel x
// without a right pixel x - d inside a width-pixel image.
std::string range_outside_image_warning(int width, int d_min, int num_disp);

// A camera with which no disparity of the searched range gives a finite,
// positive depth (d + doffs <= 0 for every d in d_min .. d_min + num_disp - 1,
// e.g. a doffs of the wrong sign): every depth, point and metric mesh vertex
// would come out invalid. `source` names the camera ("--camera", or the
// calibration file).
std::string no_depth_warning(const CameraParams& camera, const std::string& source, int d_min, int num_disp);

// More worker threads than CPUs the process may run on (`allowed`, or the
// --cpus list when given).
std::string threads_warning(int threads, int allowed_cpus, bool cpus_given);

// Left and right probably swapped. With the true left as reference, a
// pixel's match lies at x - d with d > 0; swapped, at x + d. The check needs
// no matching output: on a grid of textured 9x9 blocks of the left image it
// finds the block's best zero-mean SAD shift in -d_max..d_max (d_max = d_min +
// num_disp - 1) and counts blocks whose best shift is clearly positive or
// clearly negative (|d| >= 1, and better than the best of the other sign by a
// margin). It warns when at least kSwapMinBlocks blocks decide and the
// negative ones outnumber the positive ones kSwapRatio to 1. Only for d_min
// >= 0 (a range with negative disparities is deliberate). Gray views, same
// size. Measured on ../shared/data in docs/reliability.md.
constexpr int kSwapMinBlocks = 20;
constexpr int kSwapRatio = 2;
struct SwapVotes {
  int positive = 0, negative = 0;
};
SwapVotes swap_votes(ImageView<const std::uint8_t> left_gray, ImageView<const std::uint8_t> right_gray,
                     int d_max);
std::string swapped_warning(ImageView<const std::uint8_t> left_gray, ImageView<const std::uint8_t> right_gray,
                            int d_min, int num_disp);

}  // namespace tristereo::cli
