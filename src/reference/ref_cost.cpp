// Reference: matching cost and aggregation (docs/model.md section 2).
#include <algorithm>
#include <cstdlib>
#include <string>

#include "src/model/exp_table.hpp"
#include "src/reference/ref_match.hpp"
#include "tristereo/status.hpp"

namespace tristereo {
namespace reference {

namespace {

void check_pair(const ImageU8& left, const ImageU8& right, int y) {
  if (left.channels != 1 || right.channels != 1)
    throw Error(ErrorCode::kUnsupportedFormat, "reference matcher takes gray (1-channel) images");
  if (left.width != right.width || left.height != right.height)
    throw Error(ErrorCode::kSizeMismatch, "left and right images differ in size");
  if (y < 0 || y >= left.height)
    throw Error(ErrorCode::kInvalidArgument,
                "row y = " + std::to_string(y) + " is outside 0.." + std::to_string(left.height - 1));
}

}  // namespace

std::vector<std::vector<int>> aggregated_costs(const ImageU8& left, const ImageU8& right, int y,
                                               const std::vector<int>& xs,
                                               const StereoParams& params) {
  check_pair(left, right, y);
  const int width = left.width, height = left.height;
  const CostParams& cp = params.cost;
  const int rx = cp.window_w / 2, ry = cp.window_h / 2;
  // The weight tables are part of the model's definition (integer-built).
  std::vector<std::uint8_t> ws(256), wp(static_cast<std::size_t>(rx * rx + ry * ry + 1));
  exp_decay_table_u8(cp.asw_gamma_color, 256, ws.data());
  exp_decay_table_u8(cp.asw_gamma_proximity, static_cast<int>(wp.size()), wp.data());

  std::vector<std::vector<int>> result;
  for (int x : xs) {
    if (x < 0 || x >= width)
      throw Error(ErrorCode::kInvalidArgument, "sample x = " + std::to_string(x) + " outside the row");
    std::vector<int> ca(static_cast<std::size_t>(params.num_disp));
    for (int k = 0; k < params.num_disp; ++k) {
      const int d = params.d_min + k;
      std::uint64_t s = 0, sum_w = 0;
      for (int py = std::max(0, y - ry); py <= std::min(height - 1, y + ry); ++py) {
        for (int px = std::max(0, x - rx); px <= std::min(width - 1, x + rx); ++px) {
          const int l = left.at(px, py);
          const int r = right.at(std::clamp(px - d, 0, width - 1), py);
          const int cost = std::min(std::abs(l - r), cp.truncation);
          std::uint64_t w = 1;
          if (cp.weights == Weights::kAdaptive) {
            const int dx = px - x, dy = py - y;
            w = (std::uint64_t{ws[static_cast<std::size_t>(std::abs(l - left.at(x, y)))]} *
                 wp[static_cast<std::size_t>(dx * dx + dy * dy)]) >> 8;
          }
          s += w * static_cast<std::uint64_t>(cost);
          sum_w += w;
        }
      }
      // The model defines the mean by this Q32 reciprocal rule (not by a real
      // division), so it is transcribed in integers: inv = floor(2^32 / W),
      // Ca = (S * inv * 16 + 2^31) >> 32.
      const std::uint64_t inv = (std::uint64_t{1} << 32) / sum_w;
      ca[static_cast<std::size_t>(k)] =
          static_cast<int>((s * inv * 16 + (std::uint64_t{1} << 31)) >> 32);
    }
    result.push_back(std::move(ca));
  }
  return result;
}

}  // namespace reference
}  // namespace tristereo
