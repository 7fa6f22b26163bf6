#include "apps/stereo_pair.hpp"

#include <iostream>

#include "apps/cli_args.hpp"
#include "tristereo/gray.hpp"
#include "tristereo/params.hpp"
#include "tristereo/status.hpp"

namespace tristereo::cli {

void check_two_paths(const char* command, const std::vector<std::string>& pos) {
  if (pos.size() == 2) return;
  std::string got;
  for (const std::string& p : pos) got += (got.empty() ? "" : ", ") + p;
  throw UsageError(std::string(command) + " takes two image paths, LEFT and RIGHT; got " +
                   std::to_string(pos.size()) + (pos.empty() ? "" : " (" + got + ")") +
                   (pos.size() > 2 ? ": is an option missing its --name?" : "") + " (see --help)");
}

// The pair as the pipeline needs it: same size, same channel count. A gray
// image with an RGB one is converted (warning) rather than refused.
void check_stereo_pair(const std::string& left_path, ImageU8& left, const std::string& right_path, ImageU8& right) {
  if (left.width != right.width || left.height != right.height)
    throw Error(ErrorCode::kSizeMismatch,
                "LEFT " + left_path + " is " + std::to_string(left.width) + "x" + std::to_string(left.height) +
                    " but RIGHT " + right_path + " is " + std::to_string(right.width) + "x" +
                    std::to_string(right.height) + ": a rectified pair has one size");
  if (left.width < 2 || left.height < 2 || left.width > kMaxImageSide || left.height > kMaxImageSide)
    throw Error(ErrorCode::kInvalidArgument,
                "the pair is " + std::to_string(left.width) + "x" + std::to_string(left.height) +
                    "; matching takes 2 to " + std::to_string(kMaxImageSide) + " pixels per side");
  if (left.channels == right.channels) return;
  const bool left_gray = left.channels == 1;
  std::cerr << "warning: " << (left_gray ? "LEFT " + left_path : "RIGHT " + right_path) << " is gray but "
            << (left_gray ? "RIGHT " + right_path : "LEFT " + left_path)
            << " is RGB: matching both in gray (the RGB one converted with BT.601 weights); if they "
               "come from the same camera model, check that the right files were given\n";
  if (left_gray) right = to_gray(right);
  else left = to_gray(left);
}

}  // namespace tristereo::cli
